#!/usr/bin/python3
"""Hu's compression measured by the bed's own compaction instead of the piston's travel: for every run of a
compression sweep (sweeps/hu_compression_paper.yaml), the solid fraction of an interior slab of the bed
(away from the floor and the piston; default 10-35 mm) at every saved frame, read again from the run's
frames by `cgdem analyse` (a `profile` analysis added to the run's own), its interior strain
1 - nu0 / nu (nu0 at --start, before the piston touches), and the piston's stress against it.

    /usr/bin/python3 sweeps/hu_interior_strain.py OUT [--slab 0.01 0.035] [--start 0.656] \\
        [--strains 0.03,0.05,0.07,0.09] [--png interior_strain.png] [--csv interior_strain.csv]

Prints, per method and scale factor, the interior strain at the run's end and the stress at each
interior strain (mean over the seeds, its error against the originals' mean and the seed-to-seed
standard deviation over the originals' mean). A coarse bed whose boundary layers (at the piston and the
floor, about a particle thick) hold a larger share of its height is compacted more in its interior for
the same piston travel; this separates that from the contact law. The cgdem executable: $CGDEM, else the
repository's build/cgdem, else `cgdem` on the PATH.
"""
import argparse
import os
import re
import sys

try:
    import h5py
    import numpy as np
    import yaml
except ImportError as e:
    sys.exit(f"hu_interior_strain.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, -numpy, -yaml)")
from run_pieces import analyse, analysis_of, run_pieces, stored_scene

NAMES = {"reference": "original", "hu_method1": "Method 1", "hu_method2": "Method 2", "hu_method3": "Method 3"}


def interior(rundir, slab, start):
    """(time, interior strain, piston stress) of every frame of the run's second stage."""
    files = run_pieces(rundir)
    scene = stored_scene(files[0])
    lo, hi = scene["domain"]["lo"], scene["domain"]["hi"]
    stress = analysis_of(scene, "wall_stress")[1]
    added = {"type": "profile", "name": "interior", "axis": "z", "bins": 1,
             "region": [lo[0], lo[1], slab[0], hi[0], hi[1], slab[1]]}
    analyses = yaml.safe_dump([stress, added], default_flow_style=True, width=10000).strip()
    rows = analyse(files, [f"analyses={analyses}"])
    t, nu = rows["time"], 1 - rows["interior"]
    nu0 = np.interp(start, t, nu)
    return t, 1 - nu0 / nu, rows[stress["name"]]


def at(curve, strain, start):
    """The stress at an interior strain, on the loading after `start` (strain made monotone)."""
    t, e, s = curve
    m = t > start
    return float(np.interp(strain, np.maximum.accumulate(e[m]), s[m], left=np.nan, right=np.nan))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--slab", type=float, nargs=2, default=[0.01, 0.035], help="interior slab, z from to (m)")
    ap.add_argument("--start", type=float, default=0.656, help="time of nu0, before the piston touches (s)")
    ap.add_argument("--strains", default="0.03,0.05,0.07,0.09")
    ap.add_argument("--png")
    ap.add_argument("--csv")
    a = ap.parse_args()
    strains = [float(x) for x in a.strains.split(",")]
    runs = sorted(d for d in os.listdir(os.path.join(a.out, "runs"))
                  if os.path.exists(os.path.join(a.out, "records", d + ".txt")) and run_pieces(os.path.join(a.out, "runs", d)))
    curves = {r: interior(os.path.join(a.out, "runs", r), a.slab, a.start) for r in runs}
    cases = {}
    for r in runs:
        cases.setdefault(re.sub(r"_s\d+$", "", r), []).append(r)
    ref = {e: np.mean([at(curves[r], e, a.start) for r in cases["reference"]]) for e in strains}
    print(f"interior slab z = {a.slab[0]}-{a.slab[1]} m, nu0 at {a.start} s")
    print("case | seeds | interior strain at the end | " + " | ".join(f"stress at {e} (error, sd)" for e in strains))
    for case, members in sorted(cases.items(), key=lambda c: (c[0] != "reference", c[0])):
        m = re.fullmatch(r"(.*)_k(\d+)", case)
        label = NAMES.get(m.group(1) if m else case, case) + (f", l = {m.group(2)}" if m else "")
        ends = [curves[r][1][-1] for r in members]
        cells = []
        for e in strains:
            v = np.array([at(curves[r], e, a.start) for r in members])
            sd = v.std(ddof=1) / ref[e] if len(v) > 1 else float("nan")
            cells.append(f"{v.mean():.4g} Pa ({100 * (v.mean() / ref[e] - 1):+.1f} %, {100 * sd:.1f} %)")
        print(f"{label} | {len(members)} | {np.mean(ends):.4f} | " + " | ".join(cells))
    if a.csv:
        with open(a.csv, "w") as f:
            f.write("run,time,interior_strain,stress\n")
            for r in runs:
                for t, e, s in zip(*curves[r]):
                    f.write(f"{r},{t:.6g},{e:.6g},{s:.6g}\n")
    if a.png:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        methods = sorted({re.sub(r"_k\d+$", "", c) for c in cases if c != "reference"})
        fig, axes = plt.subplots(1, len(methods), figsize=(4.2 * len(methods), 3.8), squeeze=False)
        for ax, method in zip(axes[0], methods):
            for case, members in sorted(cases.items()):
                if case != "reference" and not case.startswith(method + "_k"):
                    continue
                colour = "black" if case == "reference" else ("C0" if case.endswith("_k2") else "C3")
                style = dict(color=colour, lw=1.8 if case == "reference" else 1)
                for k, r in enumerate(members):
                    t, e, s = curves[r]
                    m = t > a.start
                    ax.plot(e[m], 1e-3 * s[m], label=(NAMES.get(case, case.split("_")[-1].replace("k", "l = ")) if k == 0 else None), **style)
            ax.set_title(NAMES.get(method, method))
            ax.set_xlabel("interior strain 1 - nu0/nu")
            ax.set_ylabel("piston stress (kPa)")
            ax.set_xlim(0, max(strains) * 1.15)
            ax.legend(fontsize=8)
        fig.suptitle("Hu's compression against the bed's interior compaction (slab %g-%g mm)" % (1e3 * a.slab[0], 1e3 * a.slab[1]))
        fig.tight_layout()
        fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
