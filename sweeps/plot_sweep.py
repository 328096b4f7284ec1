#!/usr/bin/python3
"""Plots of a cgdem sweep (written by `cgdem sweep`, docs/sweeps.md).

usage: plot_sweep.py SWEEP.csv OUTDIR [--metrics m1,m2,...]

OUTDIR/speedup.png: speed-up against k, one curve per law (wall time, and CPU time when recorded), with the
ideal k^3 (fewer particles) and k^4 (fewer particles and a k times longer step) lines.
OUTDIR/error.png: error against speed-up, one panel per metric (relative error of the analysis' main value,
or the KS distance for a velocity distribution), one curve per law; dotted verticals at k^3 and k^4. Where a
run's mass differs from the reference's, the error against the mass-matched reference is drawn too (open
markers, dashed).

Only runs whose status is ok and only finite values are drawn: a failed run (non-zero exit, a missing or
nan figure) is left out. A panel without a finite point is dropped, and a plot without one is not written
(a stale one from an earlier sweep is removed); a one-line note says so. Each written plot is reported as
"plot_sweep.py: wrote NAME (N points)", N counting the run points drawn (not the ideal lines).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return math.nan


def finite_points(pts, xcol, ycol):
    """x and y of the rows whose x and y are both finite."""
    out = [(number(r[xcol]), number(r[ycol])) for r in pts]
    out = [(x, y) for x, y in out if math.isfinite(x) and math.isfinite(y)]
    return [p[0] for p in out], [p[1] for p in out]


def skip(outdir, name, why):
    path = os.path.join(outdir, name)
    if os.path.exists(path):
        os.remove(path)
    print(f"plot_sweep.py: {name} not written: {why}")


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
    if not rows:
        skip(outdir, "speedup.png", "no run in the table")
        skip(outdir, "error.png", "no run in the table")
        return
    ok_rows = [r for r in rows if r["status"] == "ok"]
    ref = next((r for r in ok_rows if r["run"] == "reference"), None)
    laws = sorted({r["law"] for r in rows if r["law"] != "none"})
    ks = sorted(k for k in {number(r["k"]) for r in rows} if math.isfinite(k))

    def curve(law, ycol, xcol="k"):
        # The reference starts every law's curve; a law none of whose own runs has a finite point gets none.
        pts = [r for r in ok_rows if r["law"] == law]
        if not finite_points(pts, xcol, ycol)[0]:
            return [], []
        if ref is not None:
            pts = [ref] + pts
        pts.sort(key=lambda r: number(r["k"]))
        return finite_points(pts, xcol, ycol)

    fig, ax = plt.subplots(figsize=(6, 4.5), layout="constrained")
    points = 0
    for law in laws:
        x, y = curve(law, "speedup")
        y = [v if v > 0 else math.nan for v in y]  # log axis
        x, y = [a for a, b in zip(x, y) if math.isfinite(b)], [b for b in y if math.isfinite(b)]
        if not x:
            continue
        points += len(x)
        line, = ax.plot(x, y, "o-", label=f"{law} (wall time)")
        if "speedup_cpu" in rows[0]:
            xc, yc = curve(law, "speedup_cpu")
            keep = [(a, b) for a, b in zip(xc, yc) if b > 0]
            if len(keep) > 1:
                points += len(keep)
                ax.plot([a for a, _ in keep], [b for _, b in keep], "s--", mfc="none", color=line.get_color(),
                        label=f"{law} (CPU time)")
    if points == 0:
        plt.close(fig)
        skip(outdir, "speedup.png", "no run with a finite speed-up (failed reference or runs)")
    else:
        kk = [1 + (max(ks) - 1) * i / 50 for i in range(51)] if ks and max(ks) > 1 else [1]
        ax.plot(kk, [k**3 for k in kk], "k--", lw=1, label="ideal $k^3$")
        ax.plot(kk, [k**4 for k in kk], "k:", lw=1, label="ideal $k^4$")
        ax.set_yscale("log")
        ax.set_xlabel("scale factor k")
        ax.set_ylabel("speed-up (reference wall time / run wall time)")
        ax.set_title("coarse-graining speed-up")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.savefig(f"{outdir}/speedup.png", dpi=120)
        plt.close(fig)
        print(f"plot_sweep.py: wrote speedup.png ({points} points)")

    cols = []
    for m in metrics:
        if f"ks_{m}" in rows[0]:
            cols.append((f"ks_{m}", None, f"{m}: KS distance"))
        elif f"err_{m}" in rows[0]:
            matched = f"err_mass_matched_{m}"
            cols.append((f"err_{m}", matched if matched in rows[0] else None, f"{m}: relative error"))
    if not cols:
        cols = [(c, None, c) for c in rows[0] if c.startswith("err_") and not c.startswith("err_mass_matched_")][:4]
    # Panels with at least one finite point, each with its curves.
    panels = []
    for col, matched, label in cols:
        curves = []
        for law in laws:
            x, y = curve(law, col, "speedup")
            x, y = [a for a, b in zip(x, y) if a > 0], [b for a, b in zip(x, y) if a > 0]
            xm, ym = ([], [])
            if matched:
                xm, ym = curve(law, matched, "speedup")
                xm, ym = [a for a, b in zip(xm, ym) if a > 0], [b for a, b in zip(xm, ym) if a > 0]
                # Drawn only where the masses differ enough to move the figure.
                plain = dict(zip(x, y))
                if all(abs(plain.get(a, math.inf) - b) < 1e-9 * (1 + abs(b)) for a, b in zip(xm, ym)):
                    xm, ym = [], []
            if x or xm:
                curves.append((law, x, y, xm, ym))
        if curves:
            panels.append((label, curves))
        else:
            print(f"plot_sweep.py: error.png: no panel for {label}: no finite value")
    if not panels:
        skip(outdir, "error.png", "no run with a finite error (failed reference or runs)")
        return
    n = len(panels)
    fig, axes = plt.subplots(1, n, figsize=(4.5 * n, 4), squeeze=False, layout="constrained")
    points = 0
    for ax, (label, curves) in zip(axes[0], panels):
        for law, x, y, xm, ym in curves:
            color = None
            if x:
                line, = ax.plot(x, y, "o-", label=law)
                color = line.get_color()
            if xm:
                ax.plot(xm, ym, "o--", mfc="none", color=color, label=f"{law} (mass-matched)")
            points += len(x) + len(xm)
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
    fig.savefig(f"{outdir}/error.png", dpi=120)
    plt.close(fig)
    print(f"plot_sweep.py: wrote error.png ({points} points)")


if __name__ == "__main__":
    main()
