#!/usr/bin/python3
"""Plots of a cgdem sweep (written by `cgdem sweep`, docs/sweeps.md).

usage: plot_sweep.py SWEEP.csv OUTDIR [--metrics m1,m2,...]

OUTDIR/speedup.png: speed-up against k, one curve per law (wall time, and CPU time when recorded), with the
ideal k^3 (fewer particles) and k^4 (fewer particles and a k times longer step) lines.
OUTDIR/error.png: error against speed-up, one panel per metric (relative error of the analysis' main value,
or the KS distance for a velocity distribution), one curve per law; dotted verticals at k^3 and k^4.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(s):
    try:
        return float(s)
    except ValueError:
        return math.nan


def main():
    args = sys.argv[1:]
    metrics = []
    if "--metrics" in args:
        i = args.index("--metrics")
        metrics = [m for m in args[i + 1].split(",") if m]
        del args[i:i + 2]
    path, outdir = args[0], args[1]
    with open(path) as f:
        rows = list(csv.DictReader(f))
    ref = next((r for r in rows if r["run"] == "reference"), None)
    laws = sorted({r["law"] for r in rows if r["law"] != "none"})
    ks = sorted({number(r["k"]) for r in rows})

    def curve(law, ycol, xcol="k"):
        pts = [r for r in rows if r["law"] == law and r["status"] == "ok"]
        if ref is not None and ref["status"] == "ok":
            pts = [ref] + pts
        pts.sort(key=lambda r: number(r["k"]))
        return [number(r[xcol]) for r in pts], [number(r[ycol]) for r in pts]

    fig, ax = plt.subplots(figsize=(6, 4.5))
    kk = [1 + (max(ks) - 1) * i / 50 for i in range(51)] if max(ks) > 1 else [1]
    ax.plot(kk, [k**3 for k in kk], "k--", lw=1, label="ideal $k^3$")
    ax.plot(kk, [k**4 for k in kk], "k:", lw=1, label="ideal $k^4$")
    for law in laws:
        x, y = curve(law, "speedup")
        line, = ax.plot(x, y, "o-", label=f"{law} (wall time)")
        if "speedup_cpu" in rows[0]:
            x, y = curve(law, "speedup_cpu")
            if any(math.isfinite(v) for v in y[1:]):
                ax.plot(x, y, "s--", mfc="none", color=line.get_color(), label=f"{law} (CPU time)")
    ax.set_yscale("log")
    ax.set_xlabel("scale factor k")
    ax.set_ylabel("speed-up (reference wall time / run wall time)")
    ax.set_title("coarse-graining speed-up")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{outdir}/speedup.png", dpi=120)
    plt.close(fig)

    cols = []
    for m in metrics:
        if f"ks_{m}" in rows[0]:
            cols.append((f"ks_{m}", f"{m}: KS distance"))
        elif f"err_{m}" in rows[0]:
            cols.append((f"err_{m}", f"{m}: relative error"))
    if not cols:
        cols = [(c, c) for c in rows[0] if c.startswith("err_")][:4]
    n = max(1, len(cols))
    fig, axes = plt.subplots(1, n, figsize=(4.5 * n, 4), squeeze=False)
    for ax, (col, label) in zip(axes[0], cols):
        for law in laws:
            x, y = curve(law, col, "speedup")
            ax.plot(x, y, "o-", label=law)
        for k in ks:
            if k > 1:
                ax.axvline(k**3, color="0.6", ls="--", lw=0.8)
                ax.axvline(k**4, color="0.6", ls=":", lw=0.8)
        ax.set_xscale("log")
        ax.set_xlabel("speed-up")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, title="-- $k^3$, : $k^4$", title_fontsize=7)
    fig.suptitle("error against speed-up (reference: k = 1)")
    fig.tight_layout()
    fig.savefig(f"{outdir}/error.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
