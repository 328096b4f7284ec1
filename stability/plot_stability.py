#!/usr/bin/python3
"""Energy growth rate against time step from a `cgdem stability` CSV (Hu et al. 2022, Fig. 20 method).

usage: plot_stability.py stability.csv stability.png [title]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read_stability_csv(path):
    """The '#' header line (without '#') and the rows of a `cgdem stability` CSV."""
    header, lines = "", []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                header = line[1:].strip()
            else:
                lines.append(line)
    return header, list(csv.DictReader(lines))


def main():
    src, png = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else None
    header, rows = read_stability_csv(src)
    threshold = None
    if "threshold" in header:
        threshold = float(header.split("threshold")[1].split()[0])
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    floor = 1e-9
    for variant, colour in (("conservative", "C0"), ("given", "C1")):
        pts = [r for r in rows if r["variant"] == variant]
        if not pts:
            continue
        pts.sort(key=lambda r: float(r["dt"]))
        x = [float(r["dt_over_rayleigh"]) for r in pts]
        y = []
        for r in pts:
            g = float(r["growth_per_char_time"])
            y.append(1e3 if r["blew_up"] == "1" else max(abs(g), floor))
        ax.plot(x, y, "-", color=colour, alpha=0.5)
        for xi, yi, r in zip(x, y, pts):
            g = float(r["growth_per_char_time"])
            if r["blew_up"] == "1":
                m = "x"
            elif g < 0:
                m = "v"
            else:
                m = "o"
            ax.plot([xi], [yi], m, color=colour, mfc="none" if r["stable"] == "1" else colour)
        ax.plot([], [], "o-", color=colour, label=variant)
    if threshold:
        ax.axhline(threshold, color="k", ls=":", lw=1, label="threshold %.0e" % threshold)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time step / Rayleigh time")
    ax.set_ylabel("|energy growth| per Rayleigh time (blow-up at 1e3)")
    ax.set_title(title or "cgdem stability: open = stable, filled = unstable, v = decreasing, x = blow-up",
                 fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


if __name__ == "__main__":
    main()
