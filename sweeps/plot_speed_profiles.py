#!/usr/bin/python3
"""Where in a vessel the runs' speeds differ: the mean particle speed and the share of the powder's volume
in bins of height above the floor and of distance from the vessel's axis, pooled over every output frame
from --from on (for each coordinate a panel of the mean speed and one of the volume share per mm; one
curve per run). Two runs whose profiles agree bin by bin but whose mean speeds differ put their powder in
different places; two whose profiles differ everywhere move differently.

    /usr/bin/python3 sweeps/plot_speed_profiles.py LABEL=RUN.h5 [LABEL=RUN.h5 ...] --from 0.3 --out prof.png
        [--csv prof.csv] [--axis-point 0 0] [--floor 0] [--height-edges 0,0.5,1,...] [--radius-edges ...]

Heights and distances in mm; the bins' edges default to ones that suit Hu's mixer (84 mm vessel). Runs
continued from checkpoints: repeat the label for each piece (frames pooled as by plot_speed_pdfs.py). Prints (and with --csv writes) per run and bin the mean speed and the volume share.
"""
import argparse
import sys

try:
    import h5py
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:  # the interpreter first on PATH may lack them; Debian's /usr/bin/python3 has them
    sys.exit(f"plot_speed_profiles.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, python3-matplotlib)")

from plot_speed_pdfs import labelled_runs, report, steady_frames  # noqa: E402 (beside this script)

HEIGHT_EDGES = "0,0.5,1,1.5,2,3,4,6,8,10,15,20,30"
RADIUS_EDGES = "0,10,20,25,30,34,37,39,40,41,42"


def profiles(paths, t_from, axis_point, floor, edges):
    """Per coordinate (height, distance from the axis): volume-weighted mean speed and volume share per bin."""
    sums = {c: np.zeros(len(e) - 1) for c, e in edges.items()}
    vols = {c: np.zeros(len(e) - 1) for c, e in edges.items()}
    frames = 0
    for _, g in steady_frames(paths, t_from):
        x, v, r = g["position"][()], g["velocity"][()], g["radius"][()]
        speed, volume = np.sqrt((v * v).sum(axis=1)), r**3
        coord = {"height": 1e3 * (x[:, 2] - floor),
                 "radius": 1e3 * np.hypot(x[:, 0] - axis_point[0], x[:, 1] - axis_point[1])}
        for c, e in edges.items():
            b = np.digitize(coord[c], e) - 1
            ok = (b >= 0) & (b < len(e) - 1)
            np.add.at(sums[c], b[ok], (speed * volume)[ok])
            np.add.at(vols[c], b[ok], volume[ok])
        frames += 1
    out = {}
    for c in edges:
        with np.errstate(invalid="ignore", divide="ignore"):
            out[c] = (np.where(vols[c] > 0, sums[c] / vols[c], np.nan), vols[c] / vols[c].sum())
    return out, frames


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=RUN.h5 (repeat a label to pool several pieces)")
    ap.add_argument("--from", dest="t_from", type=float, required=True, help="first frame time pooled, s")
    ap.add_argument("--out", required=True)
    ap.add_argument("--csv")
    ap.add_argument("--axis-point", type=float, nargs=2, default=[0.0, 0.0], help="x y of the vessel's axis, m")
    ap.add_argument("--floor", type=float, default=0.0, help="height of the floor, m")
    ap.add_argument("--height-edges", default=HEIGHT_EDGES, help="mm, comma-separated")
    ap.add_argument("--radius-edges", default=RADIUS_EDGES, help="mm, comma-separated")
    a = ap.parse_args()

    edges = {"height": np.array([float(s) for s in a.height_edges.split(",")]),
             "radius": np.array([float(s) for s in a.radius_edges.split(",")])}
    data = {label: profiles(paths, a.t_from, a.axis_point, a.floor, edges)
            for label, paths in labelled_runs(a.runs).items()}

    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex="col")
    names = {"height": "height above the floor (mm)", "radius": "distance from the axis (mm)"}
    lines = ["run,coordinate,bin_from_mm,bin_to_mm,mean_speed,volume_share"]
    for col, c in enumerate(edges):
        centres = 0.5 * (edges[c][1:] + edges[c][:-1])
        for label, (prof, frames) in data.items():
            speed, share = prof[c]
            style = dict(marker="o", ms=3, lw=1.4, label=f"{label} ({frames} frames)")
            axes[0, col].plot(centres, speed, **style)
            axes[1, col].plot(centres, share / np.diff(edges[c]), **style)
            for i in range(len(centres)):
                lines.append(f"{label},{c},{edges[c][i]:g},{edges[c][i + 1]:g},{speed[i]:.4g},{share[i]:.4g}")
        axes[0, col].set_ylabel("mean speed in the bin (m/s)")
        axes[1, col].set_ylabel("share of the powder's volume per mm")
        axes[1, col].set_xlabel(names[c])
    axes[0, 0].legend(fontsize=8)
    fig.suptitle(f"speed profiles pooled from t = {a.t_from:g} s")
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    report(lines, a.csv, a.out)


if __name__ == "__main__":
    main()
