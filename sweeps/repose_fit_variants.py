#!/usr/bin/python3
"""How much an angle of repose depends on the fit's choices: refits the last frame of every run of a
cylinder-lift sweep (DIR/runs/<run>/run.h5) with the engine's method (docs/sweeps.md, angle_of_repose:
per radial bin the highest particle top of each azimuthal sector, averaged over the sectors, a line fitted
through the bins between 20 % and 80 % of the pile's height) under other bin widths, sector counts and the
median over the sectors instead of the mean, and prints each run's angles and, per case, the mean, the
seed-to-seed standard deviation and the error of the mean against the first reference run.

    /usr/bin/python3 sweeps/repose_fit_variants.py DIR [--center 0 0] [--floor 0]
"""
import argparse
import os
import re
import sys

try:
    import h5py
    import numpy as np
except ImportError as e:
    sys.exit(f"repose_fit_variants.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, python3-numpy)")

VARIANTS = [(0.001, 8, "mean"), (0.002, 8, "mean"), (0.002, 16, "mean"), (0.002, 8, "median")]


def last_frame(path):
    with h5py.File(path, "r") as f:
        g = f["frames"][sorted(f["frames"].keys())[-1]]
        return g["position"][()], g["radius"][()]


def angle(x, r, centre, floor, bin_width, sectors, stat):
    dx, dy = x[:, 0] - centre[0], x[:, 1] - centre[1]
    top = x[:, 2] + r - floor
    height = top.max()
    sector = np.minimum(((np.arctan2(dy, dx) + np.pi) / (2 * np.pi) * sectors).astype(int), sectors - 1)
    ring = (np.hypot(dx, dy) / bin_width).astype(int)
    radii, heights = [], []
    for b in range(ring.max() + 1):
        tops = [top[(ring == b) & (sector == s)].max() for s in range(sectors) if ((ring == b) & (sector == s)).any()]
        if not tops:
            continue
        h = np.mean(tops) if stat == "mean" else np.median(tops)
        if 0.2 * height <= h <= 0.8 * height:
            radii.append((b + 0.5) * bin_width)
            heights.append(h)
    if len(radii) < 2:
        return float("nan")
    return float(np.degrees(np.arctan(-np.polyfit(radii, heights, 1)[0])))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--center", type=float, nargs=2, default=[0.0, 0.0])
    ap.add_argument("--floor", type=float, default=0.0)
    a = ap.parse_args()
    runs = sorted(d for d in os.listdir(os.path.join(a.dir, "runs"))
                  if os.path.exists(os.path.join(a.dir, "runs", d, "run.h5"))
                  and os.path.exists(os.path.join(a.dir, "records", d + ".txt")))
    names = [f"{w * 1e3:g}mm/{s}{'' if st == 'mean' else '/median'}" for w, s, st in VARIANTS]
    print("run," + ",".join(names))
    angles = {}
    for run in runs:
        x, r = last_frame(os.path.join(a.dir, "runs", run, "run.h5"))
        angles[run] = [angle(x, r, a.center, a.floor, *v) for v in VARIANTS]
        print(run + "," + ",".join(f"{v:.1f}" for v in angles[run]))
    refs = [k for k in runs if k.startswith("reference")]
    if not refs:
        return
    ref = np.mean([angles[k] for k in refs], axis=0)
    cases = sorted({re.sub(r"_s\d+$", "", k) for k in runs if not k.startswith("reference")})
    print("case,seeds," + ",".join(f"{n} mean,sd,err" for n in names))
    for c in cases:
        m = np.array([angles[k] for k in runs if re.sub(r"_s\d+$", "", k) == c])
        sd = m.std(axis=0, ddof=1) if len(m) > 1 else np.zeros(len(VARIANTS))
        cells = [f"{mu:.1f},{s:.1f},{mu / rv - 1:+.3f}" for mu, s, rv in zip(m.mean(axis=0), sd, ref)]
        print(f"{c},{len(m)}," + ",".join(cells))
    print(f"reference ({', '.join(refs)})," + ",".join(f"{v:.1f}" for v in ref))


if __name__ == "__main__":
    main()
