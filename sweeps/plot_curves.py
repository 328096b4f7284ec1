#!/usr/bin/python3
"""Overlays one time series of every run of a sweep, so a metric's whole curve can be compared, not only its
final value: e.g. the piston stress against strain of each law and k against the k = 1 reference.

    /usr/bin/python3 sweeps/plot_curves.py SWEEP_DIR --x stress_strain --y stress --out curve.png \
        [--from 0.32] [--to 0.58] [--xlabel ...] [--ylabel ...] [--yscale 1e-3] [--title ...]

Reads SWEEP_DIR/runs/<run>/run.h5 (/series/<x>, /series/<y>, /series/time), preceded by its run.part<N>.h5
when the run was continued from checkpoints and by its first_stage.h5 when it ran in two stages; the reference
runs (reference, reference_s<seed>) are drawn black.
--from/--to keep the output frames with time in [from, to] (a test phase of a multi-phase run).
"""
import argparse
import os
import sys

try:
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:  # the interpreter first on PATH may lack them; Debian's /usr/bin/python3 has them
    sys.exit(f"plot_curves.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, python3-matplotlib)")
from run_pieces import run_pieces


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sweep_dir")
    ap.add_argument("--x", required=True, help="series on the x axis (e.g. stress_strain, time)")
    ap.add_argument("--y", required=True, help="series on the y axis (e.g. stress)")
    ap.add_argument("--out", required=True, help="PNG file to write")
    ap.add_argument("--from", dest="t0", type=float, default=float("-inf"))
    ap.add_argument("--to", dest="t1", type=float, default=float("inf"))
    ap.add_argument("--xlabel")
    ap.add_argument("--ylabel")
    ap.add_argument("--yscale", type=float, default=1.0, help="multiply y by this (e.g. 1e-3 for kPa)")
    ap.add_argument("--title")
    a = ap.parse_args()

    runs_dir = os.path.join(a.sweep_dir, "runs")
    if not os.path.isdir(runs_dir):
        sys.exit(f"plot_curves.py: {runs_dir} does not exist; run the sweep first (cgdem sweep ... --out {a.sweep_dir})")
    runs = sorted(os.listdir(runs_dir), key=lambda r: (not r.startswith("reference"), r))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    drawn = 0
    for run in runs:
        if not os.path.exists(os.path.join(runs_dir, run, "run.h5")):
            continue
        t, x, y = [], [], []
        for piece in run_pieces(os.path.join(runs_dir, run), with_first_stage=True):
            with h5py.File(piece, "r") as f:
                s = f["series"]
                if a.x not in s or a.y not in s:
                    sys.exit(f"plot_curves.py: {piece} has no series '{a.x}' or '{a.y}'; known: {', '.join(s.keys())}")
                # A piece starts at its checkpoint: a time two pieces both hold is drawn once.
                nt = s["time"][:]
                t, x, y = t + list(nt), x + list(s[a.x][:]), y + list(s[a.y][:] * a.yscale)
        order = sorted(range(len(t)), key=lambda i: t[i])
        seen, keep_idx = set(), []
        for i in order:
            if t[i] not in seen and a.t0 <= t[i] <= a.t1:
                seen.add(t[i])
                keep_idx.append(i)
        x = [x[i] for i in keep_idx]
        y = [y[i] for i in keep_idx]
        style = dict(color="black", lw=2.2) if run.startswith("reference") else dict(lw=1.4)
        ax.plot(x, y, label=run.replace("_k", ", k = ").replace("_s", ", seed "), **style)
        drawn += 1
    if drawn == 0:
        sys.exit(f"plot_curves.py: no runs/<run>/run.h5 under {a.sweep_dir}")
    ax.set_xlabel(a.xlabel or a.x)
    ax.set_ylabel(a.ylabel or a.y)
    if a.title:
        ax.set_title(a.title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"wrote {a.out} ({drawn} runs)")


if __name__ == "__main__":
    main()
