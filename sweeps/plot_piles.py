#!/usr/bin/python3
"""Piles of a cylinder-lift sweep side by side, like Chen & Elliott (2020) Fig. 7: panel (a) the original pile,
then one panel per coarse-grained run with the original's left half (red) over the coarse pile (blue) and the
original pile's height as an orange dash-dot line. Each panel is a vertical slab |y - cy| < slab through the
pile's axis, particles drawn at their radius; the title gives the angle and height of the last frame
(/series/<metric>, /series/<metric>_height) with the fit's standard error.

    /usr/bin/python3 sweeps/plot_piles.py SWEEP_DIR --out piles.png [--runs reference_s1,chen_elliott_k2_s1,...]
        [--metric repose] [--slab 0.001] [--center 0 0]

Without --runs: the first reference run and the first seed of every coarse-grained case. Runs continued from
checkpoints are read from their last piece (run.h5).
"""
import argparse
import os
import sys

try:
    import h5py
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import EllipseCollection
except ImportError as e:  # the interpreter first on PATH may lack them; Debian's /usr/bin/python3 has them
    sys.exit(f"plot_piles.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, python3-matplotlib)")


def last_frame(path, metric):
    with h5py.File(path, "r") as f:
        frames = sorted(f["frames"].keys())
        g = f["frames"][frames[-1]]
        pos, rad = g["position"][:].reshape(-1, 3), g["radius"][:]
        s = f["series"]
        def final(name):
            return float(s[name][-1]) if name in s else float("nan")
        return pos, rad, final(metric), final(metric + "_stderr"), final(metric + "_height")


def slab(pos, rad, center, width):
    keep = abs(pos[:, 1] - center[1]) < width
    return pos[keep, 0] - center[0], pos[keep, 2], rad[keep]


def draw(ax, x, z, r, color, alpha=0.85):
    ax.add_collection(EllipseCollection(2 * r, 2 * r, 0, units="xy", offsets=list(zip(x, z)),
                                        transOffset=ax.transData, facecolors=color, edgecolors="none",
                                        alpha=alpha))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sweep_dir")
    ap.add_argument("--out", required=True)
    ap.add_argument("--runs", help="comma-separated run names, the reference first")
    ap.add_argument("--metric", default="repose", help="the angle_of_repose analysis' name")
    ap.add_argument("--slab", type=float, default=0.001, help="half-width of the slab drawn (m)")
    ap.add_argument("--center", type=float, nargs=2, default=[0.0, 0.0])
    a = ap.parse_args()

    runs_dir = os.path.join(a.sweep_dir, "runs")
    if not os.path.isdir(runs_dir):
        sys.exit(f"plot_piles.py: {runs_dir} does not exist; run the sweep first")
    have = sorted(r for r in os.listdir(runs_dir) if os.path.exists(os.path.join(runs_dir, r, "run.h5")))
    if a.runs:
        runs = a.runs.split(",")
        missing = [r for r in runs if r not in have]
        if missing:
            sys.exit(f"plot_piles.py: no run.h5 for {', '.join(missing)} under {runs_dir}")
    else:
        refs = [r for r in have if r.startswith("reference")]
        cases = {}
        for r in have:
            if not r.startswith("reference"):
                cases.setdefault(r.rsplit("_s", 1)[0] if "_s" in r else r, r)
        runs = refs[:1] + sorted(cases.values())
    if not runs or not runs[0].startswith("reference"):
        sys.exit("plot_piles.py: no finished reference run (runs/reference*/run.h5)")

    ref = last_frame(os.path.join(runs_dir, runs[0], "run.h5"), a.metric)
    rx, rz, rr = slab(ref[0], ref[1], a.center, a.slab)
    fig, axes = plt.subplots(1, len(runs), figsize=(4.2 * len(runs), 3.4), sharey=True, squeeze=False)
    for ax, run in zip(axes[0], runs):
        pos, rad, angle, stderr, height = last_frame(os.path.join(runs_dir, run, "run.h5"), a.metric)
        if run == runs[0]:
            draw(ax, rx, rz, rr, "tab:red")
            label = "original"
        else:
            x, z, r = slab(pos, rad, a.center, a.slab)
            draw(ax, x, z, r, "tab:blue")
            left = rx < 0
            draw(ax, rx[left], rz[left], rr[left], "tab:red", 0.9)
            label = run.replace("_k", ", k = ").replace("_s", ", seed ")
        ax.axhline(ref[4], color="orange", ls="-.", lw=1.2)
        ax.set_title(f"{label}\n{angle:.1f} +- {stderr:.1f} deg, height {1e3 * height:.1f} mm", fontsize=9)
        ax.set_aspect("equal")
        span = max(float(np.percentile(abs(rx), 99.5)), 1e-3) * 1.1  # stray rollers far out are not shown
        ax.set_xlim(-span, span)
        ax.set_ylim(0, max(rz.max() + rr.max(), height) * 1.15)
        ax.set_xlabel("x (m)")
    axes[0][0].set_ylabel("z (m)")
    fig.tight_layout()
    fig.savefig(a.out, dpi=130)
    print(f"plot_piles.py: wrote {a.out} ({len(runs)} panels: {', '.join(runs)})")


if __name__ == "__main__":
    main()
