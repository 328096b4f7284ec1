#!/usr/bin/python3
"""Energy growth rate against time step, several systems in one plot, like Hu et al. 2022's Fig. 20.

Each LABEL=stability.csv (from `cgdem stability ... --time T --samples N`) gives one curve: the fitted
growth of the total energy per Rayleigh time (each file's own, or the one given by --rayleigh-time, e.g.
the original particles'), with bars of two standard errors;
a filled marker grows beyond them (Hu's criterion: the rate is positive), an open one does not, x is a
blow-up (drawn at the top).

usage: plot_growth_rate.py OUT.png LABEL=stability.csv [LABEL=stability.csv ...]
           [--rayleigh-time SECONDS] [--variant conservative] [--title TEXT]
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from plot_stability import read_stability_csv


def read(path, variant):
    header, rows = read_stability_csv(path)
    rows = sorted((r for r in rows if r["variant"] == variant), key=lambda r: float(r["dt"]))
    tr = float(header.split("rayleigh_time")[1].split()[0]) if "rayleigh_time" in header else None
    return rows, tr


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("runs", nargs="+", help="LABEL=stability.csv")
    ap.add_argument("--variant", default="conservative")
    ap.add_argument("--rayleigh-time", type=float, default=None,
                    help="express every curve's rate per this time (default: each file's own T_R)")
    ap.add_argument("--title", default=None)
    a = ap.parse_args()
    fig, ax = plt.subplots(figsize=(6.8, 4.4))
    top = 0
    curves = []
    for k, spec in enumerate(a.runs):
        label, path = spec.rsplit("=", 1)
        rows, tr = read(path, a.variant)
        scale = (a.rayleigh_time / tr) if (a.rayleigh_time and tr) else 1.0
        curves.append((label, rows, scale, f"C{k}"))
        for r in rows:
            if r["blew_up"] != "1":
                top = max(top, abs(float(r["growth_per_char_time"]) * scale) +
                          2 * float(r.get("growth_std_error") or 0) * scale)
    top = top * 1.5 if top > 0 else 1.0
    for label, rows, scale, colour in curves:
        xs, ys = [], []
        for r in rows:
            x = float(r["dt"]) * 1e6
            if r["blew_up"] == "1":
                ax.plot([x], [top], "x", color=colour, ms=8)
                continue
            g = float(r["growth_per_char_time"]) * scale
            err = 2 * float(r.get("growth_std_error") or 0) * scale
            grows = r.get("grows", "0") == "1"
            ax.errorbar([x], [g], yerr=[err], fmt="o", color=colour, mfc=colour if grows else "none", capsize=3)
            xs.append(x)
            ys.append(g)
        ax.plot(xs, ys, "-", color=colour, alpha=0.6, label=label)
    ax.axhline(0, color="k", lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1e-7)
    ax.set_xlabel("time step (us)")
    unit = "per original Rayleigh time" if a.rayleigh_time else "per Rayleigh time"
    ax.set_ylabel(f"energy growth rate {unit}")
    ax.set_title(a.title or "filled: above zero beyond 2 standard errors (Hu's criterion); x: blow-up",
                 fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)


if __name__ == "__main__":
    main()
