#!/usr/bin/python3
"""How much an angle of repose depends on the fit's choices: the engine's `angle_of_repose` analysis
(docs/sweeps.md: per radial bin the highest particle top of each azimuthal sector, averaged over the
sectors, a line fitted through the bins between 20 % and 80 % of the pile's height) evaluated again by
`cgdem analyse` on the last frame of every run of a cylinder-lift sweep (DIR/runs/<run>/run.h5) under other
bin widths, sector counts and the median over the sectors instead of the mean; prints each run's angles
and, per case, the mean, the seed-to-seed standard deviation and the error of the mean against the
reference runs. The cgdem executable: $CGDEM, else the repository's build/cgdem, else `cgdem` on the PATH.

    /usr/bin/python3 sweeps/repose_fit_variants.py DIR [--center 0 0] [--floor 0]
"""
import argparse
import os
import re
import sys

try:
    import h5py  # noqa: F401 (run_pieces reads the stored scenes with it)
    import numpy as np
    import yaml  # noqa: F401
except ImportError as e:
    sys.exit(f"repose_fit_variants.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, -numpy, -yaml)")
from run_pieces import analyse, analysis_of, stored_scene

VARIANTS = [(0.001, 8, "mean"), (0.002, 8, "mean"), (0.002, 16, "mean"), (0.002, 8, "median")]


def angles(path, center, floor):
    """The angle of the run's last frame under each of VARIANTS: its own first angle_of_repose analysis,
    with the variant's bin width, sectors and sector statistic (and the given centre and floor)."""
    index, spec = analysis_of(stored_scene(path), "angle_of_repose")
    name = spec.get("name", "angle_of_repose")
    out = []
    for bin_width, sectors, statistic in VARIANTS:
        sets = {"bin_width": bin_width, "sectors": sectors, "sector_statistic": statistic,
                "center": f"[{center[0]!r}, {center[1]!r}]", "floor": floor}
        last = analyse([path], [f"analyses.{index}.{key}={value}" for key, value in sets.items()], per_frame=False)
        out.append(last[name])
    return out


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
    found = {}
    for run in runs:
        found[run] = angles(os.path.join(a.dir, "runs", run, "run.h5"), a.center, a.floor)
        print(run + "," + ",".join(f"{v:.1f}" for v in found[run]))
    refs = [k for k in runs if k.startswith("reference")]
    if not refs:
        return
    ref = np.mean([found[k] for k in refs], axis=0)
    cases = sorted({re.sub(r"_s\d+$", "", k) for k in runs if not k.startswith("reference")})
    print("case,seeds," + ",".join(f"{n} mean,sd,err" for n in names))
    for c in cases:
        m = np.array([found[k] for k in runs if re.sub(r"_s\d+$", "", k) == c])
        sd = m.std(axis=0, ddof=1) if len(m) > 1 else np.zeros(len(VARIANTS))
        cells = [f"{mu:.1f},{s:.1f},{mu / rv - 1:+.3f}" for mu, s, rv in zip(m.mean(axis=0), sd, ref)]
        print(f"{c},{len(m)}," + ",".join(cells))
    print(f"reference ({', '.join(refs)})," + ",".join(f"{v:.1f}" for v in ref))


if __name__ == "__main__":
    main()
