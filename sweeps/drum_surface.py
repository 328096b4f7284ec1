#!/usr/bin/python3
"""The dynamic angle of every run of a drum sweep, from its saved frames: the bed's free-surface angle of
each frame by the engine's `drum_angle` method (drivers/analyses.cpp: the cross-section seen along the axis in
square cells of 4 largest radii, a cell being bed at a solid fraction of 0.2, each column's surface the top of
the run of bed cells rising from its lowest one, points within 1.5 cells of the drum wall dropped, a total
least squares line through the central fit fraction), its mean and standard deviation over a time window,
and each law's mean over the seeds against the reference's.

    /usr/bin/python3 sweeps/drum_surface.py SWEEP_DIR --scene sweeps/chen_drum_paper.yaml --from 1.5 --to 7.5 \\
        [--fit-fraction 0.6] [--cell-factor 4] [--wall-layer 1.5] [--bed-fraction 0.2] [--png angle_time.png] \\
        [--csv angles.csv]

Reads SWEEP_DIR/runs/<run>/run.part<N>.h5 then run.h5 (a run continued from checkpoints) and the drum
(the scene's first `drum_angle` analysis: its wall's point, axis and radius; gravity gives "up").
--cell-factor, --wall-layer and --bed-fraction vary the cell width (in largest radii), the dropped wall layer
(in cells) and the solid fraction of a bed cell, to show how much of an angle is the method's. It recomputes what the runs' own analysis
computes, and serves for runs made before that analysis ignored the powder coating the drum's wall.
"""
import argparse
import glob
import math
import os
import re
import sys

try:
    import h5py
    import numpy as np
    import yaml
except ImportError as e:  # the interpreter first on PATH may lack them; Debian's /usr/bin/python3 has them
    sys.exit(f"drum_surface.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, -numpy, -yaml)")


def drum_of(scene_path):
    scene = yaml.safe_load(open(scene_path))
    analysis = next(a for a in scene.get("analyses", []) if a.get("type") == "drum_angle")
    wall = next(w for w in scene["walls"] if w["name"] == analysis["drum"])
    axis = np.array(wall["axis"], float)
    axis /= np.linalg.norm(axis)
    g = np.array(scene["gravity"], float)
    up = -(g - g.dot(axis) * axis)
    up /= np.linalg.norm(up)
    return np.array(wall["point"], float), axis, up, float(wall["radius"])


def frame_angle(pos, rad, drum, cell_factor=4.0, wall_layer=1.5, bed_fraction=0.2, fit_fraction=0.6):
    """The engine's drum_angle of one frame: (angle in degrees, points fitted)."""
    center, axis, up, drum_radius = drum
    cell = cell_factor * rad.max()
    d = pos - center
    u, v, w = d @ np.cross(up, axis), d @ up, d @ axis
    length = (w + rad).max() - (w - rad).min()
    iu, iv = np.floor(u / cell).astype(np.int64), np.floor(v / cell).astype(np.int64)
    volume, top = {}, {}
    for a, b, vol, t in zip(iu, iv, 4.0 / 3.0 * math.pi * rad**3, v + rad):
        volume[a, b] = volume.get((a, b), 0.0) + vol
        top[a, b] = max(top.get((a, b), -math.inf), t)
    bed = {}
    for (a, b), vol in volume.items():
        if vol >= bed_fraction * cell * cell * length:
            bed.setdefault(a, set()).add(b)
    inner = drum_radius - wall_layer * cell
    pts = []
    for a, cells in bed.items():
        b = min(cells)
        while b + 1 in cells:
            b += 1
        uc, vt = (a + 0.5) * cell, top[a, b]
        if uc * uc + vt * vt < inner * inner:
            pts.append((uc, vt))
    if not pts:
        return float("nan"), 0
    p = np.array(pts)
    lo, hi = p[:, 0].min(), p[:, 0].max()
    p = p[np.abs(p[:, 0] - 0.5 * (lo + hi)) <= 0.5 * fit_fraction * (hi - lo)]
    if len(p) < 2:
        return float("nan"), len(p)
    m = p - p.mean(axis=0)
    suu, svv, suv = (m[:, 0] ** 2).mean(), (m[:, 1] ** 2).mean(), (m[:, 0] * m[:, 1]).mean()
    return abs(math.degrees(0.5 * math.atan2(2 * suv, suu - svv))), len(p)


def run_files(rundir):
    parts = sorted(glob.glob(os.path.join(rundir, "run.part*.h5")), key=lambda s: int(re.findall(r"part(\d+)", s)[-1]))
    return parts + [os.path.join(rundir, "run.h5")]


def run_series(rundir, drum, t0, t1, **kw):
    frames = {}  # time -> (file, frame name); a later piece's frame replaces an earlier one of the same time
    for fn in run_files(rundir):
        if not os.path.exists(fn):
            continue
        with h5py.File(fn, "r") as f:
            for name in f["frames"]:
                t = round(float(f["frames"][name].attrs["time"]), 9)
                if t0 <= t <= t1:
                    frames[t] = (fn, name)
    times, angles = [], []
    for t in sorted(frames):
        fn, name = frames[t]
        with h5py.File(fn, "r") as f:
            g = f["frames"][name]
            angle, _ = frame_angle(g["position"][:], g["radius"][:], drum, **kw)
        times.append(t)
        angles.append(angle)
    return np.array(times), np.array(angles)


def law_of(run):
    return "reference" if run.startswith("reference") else re.sub(r"_s\d+$", "", run)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sweep_dir")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--from", dest="t0", type=float, required=True, help="start of the averaging window (s)")
    ap.add_argument("--to", dest="t1", type=float, default=float("inf"))
    ap.add_argument("--fit-fraction", type=float, default=0.6)
    ap.add_argument("--cell-factor", type=float, default=4.0, help="cell width in largest radii")
    ap.add_argument("--wall-layer", type=float, default=1.5, help="dropped wall layer in cells")
    ap.add_argument("--bed-fraction", type=float, default=0.2, help="solid fraction of a bed cell")
    ap.add_argument("--png", help="angle against time of every run (the whole run, window marked)")
    ap.add_argument("--csv", help="every frame's angle of every run")
    a = ap.parse_args()
    drum = drum_of(a.scene)
    kw = dict(cell_factor=a.cell_factor, wall_layer=a.wall_layer, bed_fraction=a.bed_fraction, fit_fraction=a.fit_fraction)
    runs = sorted(d for d in os.listdir(os.path.join(a.sweep_dir, "runs")) if not d.startswith("."))
    series = {r: run_series(os.path.join(a.sweep_dir, "runs", r), drum, 0 if a.png or a.csv else a.t0, a.t1, **kw) for r in runs}
    per_run = {}
    print(f"window {a.t0}-{a.t1} s; cell {a.cell_factor} radii, wall layer {a.wall_layer} cells, bed fraction {a.bed_fraction}, fit fraction {a.fit_fraction}")
    print("run, frames, mean angle (deg), std over the window")
    for r in runs:
        t, ang = series[r]
        sel = ang[(t >= a.t0) & (t <= a.t1) & np.isfinite(ang)]
        per_run[r] = (sel.mean() if len(sel) else float("nan"), sel.std(ddof=1) if len(sel) > 1 else float("nan"), len(sel))
        print(f"{r}, {len(sel)}, {per_run[r][0]:.2f}, {per_run[r][1]:.2f}")
    laws = {}
    for r in runs:
        laws.setdefault(law_of(r), []).append(per_run[r][0])
    ref = np.mean(laws.get("reference", [float("nan")]))
    print("law, seeds, mean over seeds (deg), seed sd, error of the mean, scatter (sd / reference)")
    for law, vals in laws.items():
        v = np.array(vals)
        sd = v.std(ddof=1) if len(v) > 1 else float("nan")
        print(f"{law}, {len(v)}, {v.mean():.2f}, {sd:.2f}, {100 * (v.mean() - ref) / ref:+.1f} %, {100 * sd / ref:.1f} %")
    if a.csv:
        with open(a.csv, "w") as out:
            out.write("run,time,angle_deg\n")
            for r in runs:
                for t, ang in zip(*series[r]):
                    out.write(f"{r},{t:.6g},{ang:.6g}\n")
    if a.png:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(10, 5))
        for r in runs:
            t, ang = series[r]
            ref_run = law_of(r) == "reference"
            ax.plot(t, ang, color="black" if ref_run else None, lw=1.6 if ref_run else 0.8, label=r)
        ax.axvspan(a.t0, min(a.t1, max(t.max() for t, _ in series.values())), color="0.9", zorder=0)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("bed surface angle (deg)")
        ax.set_title(os.path.basename(os.path.normpath(a.sweep_dir)) + ": averaging window shaded")
        ax.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
