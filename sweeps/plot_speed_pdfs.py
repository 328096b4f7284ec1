#!/usr/bin/python3
"""Speed distributions of several runs at steady state, like Hu et al. 2022 Figs. 12-18: for each run the
particle speeds |v| of every output frame from --from on are pooled and binned into a probability density
(0 to --max m/s, --bins bins); one curve per run. With --reference LABEL the table adds each run's
first-Wasserstein distance (W1, m/s) and Kolmogorov-Smirnov distance to that run's pooled speeds and the
relative error of the mean speed.

    /usr/bin/python3 sweeps/plot_speed_pdfs.py LABEL=RUN.h5 [LABEL=RUN.h5 ...] --from 0.4 --out pdf.png
        [--csv table.csv] [--reference LABEL] [--title TEXT] [--max 1.5] [--bins 30]

Prints (and with --csv writes) per run: frames pooled, particles, mean, sd, median and 90th percentile speed,
the standard deviation of the frames' mean speeds (frame_mean_sd: how much the mean speed itself wanders at
steady state, the scale against which a difference of means is noise or not), and the distances above.
Runs continued from checkpoints: give the last piece (run.h5), or several pieces with the same label (their
frames are pooled).
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
    sys.exit(f"plot_speed_pdfs.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, python3-matplotlib)")


def steady_frames(paths, t_from):
    """Each output frame at t >= t_from in the files, once, as (time, frame group). Output times fall up to a
    few steps off their nominal value (the step does not divide the output interval), and a run's closing
    frame can repeat its last output frame a step later, so times within 1e-4 s count as equal."""
    times = []
    for path in paths:
        with h5py.File(path, "r") as f:
            for name in sorted(f["frames"].keys()):
                g = f["frames"][name]
                t = float(g.attrs["time"])
                if t < t_from - 1e-4 or any(abs(t - u) < 1e-4 for u in times):
                    continue
                times.append(t)
                yield t, g
    if not times:
        sys.exit(f"{sys.argv[0]}: no frame at t >= {t_from} s in {', '.join(paths)}")


def labelled_runs(items):
    """LABEL=RUN.h5 arguments as {label: [paths]}, a repeated label collecting the pieces of one run."""
    files = {}
    for item in items:
        label, sep, path = item.partition("=")
        if not sep:
            sys.exit(f"{sys.argv[0]}: '{item}' is not LABEL=RUN.h5")
        files.setdefault(label, []).append(path)
    return files


def report(lines, csv, png):
    """Prints the table's lines, writes them to csv when given, and says which files were written."""
    print("\n".join(lines))
    if csv:
        with open(csv, "w") as f:
            f.write("\n".join(lines) + "\n")
    print(f"{sys.argv[0]}: wrote {png}" + (f" and {csv}" if csv else ""))


def pooled_speeds(paths, t_from):
    """Speeds of every frame at t >= t_from in the files, pooled; the frame count, the particle count and
    each frame's mean speed."""
    speeds, particles = [], 0
    for _, g in steady_frames(paths, t_from):
        v = g["velocity"][()]
        speeds.append(np.sqrt((v * v).sum(axis=1)))
        particles = v.shape[0]
    return np.concatenate(speeds), len(speeds), particles, np.array([s.mean() for s in speeds])


def w1(a, b):
    """First Wasserstein distance between two samples (the area between their CDFs)."""
    grid = np.sort(np.concatenate([a, b]))
    ca = np.searchsorted(np.sort(a), grid[:-1], side="right") / a.size
    cb = np.searchsorted(np.sort(b), grid[:-1], side="right") / b.size
    return float(np.sum(np.abs(ca - cb) * np.diff(grid)))


def ks(a, b):
    grid = np.sort(np.concatenate([a, b]))
    ca = np.searchsorted(np.sort(a), grid, side="right") / a.size
    cb = np.searchsorted(np.sort(b), grid, side="right") / b.size
    return float(np.max(np.abs(ca - cb)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=RUN.h5 (repeat a label to pool several pieces)")
    ap.add_argument("--from", dest="t_from", type=float, required=True, help="first frame time pooled, s")
    ap.add_argument("--out", required=True)
    ap.add_argument("--csv")
    ap.add_argument("--reference")
    ap.add_argument("--title", default="")
    ap.add_argument("--max", type=float, default=1.5)
    ap.add_argument("--bins", type=int, default=30)
    a = ap.parse_args()

    data = {label: pooled_speeds(paths, a.t_from) for label, paths in labelled_runs(a.runs).items()}
    if a.reference and a.reference not in data:
        sys.exit(f"plot_speed_pdfs.py: --reference {a.reference} is not one of the labels {list(data)}")

    edges = np.linspace(0, a.max, a.bins + 1)
    centres = 0.5 * (edges[1:] + edges[:-1])
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    rows = []
    for label, (s, frames, n, frame_means) in data.items():
        pdf, _ = np.histogram(np.clip(s, 0, a.max), bins=edges, density=True)
        ref = label == a.reference
        ax.plot(centres, pdf, "k-" if ref else "-", lw=2.2 if ref else 1.4, marker=None if ref else "o", ms=3,
                label=label)
        row = {"run": label, "frames": frames, "particles": n, "mean": s.mean(), "sd": s.std(),
               "median": float(np.median(s)), "p90": float(np.percentile(s, 90)),
               "frame_mean_sd": float(frame_means.std(ddof=1)) if frames > 1 else float("nan")}
        if a.reference:
            r = data[a.reference][0]
            row.update({"err_mean": s.mean() / r.mean() - 1, "w1": w1(s, r), "ks": ks(s, r)})
        rows.append(row)
    ax.set_xlabel("particle speed |v| (m/s)")
    ax.set_ylabel("probability density (s/m)")
    ax.set_xlim(0, a.max)
    ax.set_ylim(bottom=0)
    ax.set_title(a.title or f"speeds pooled from t = {a.t_from:g} s")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)

    cols = list(rows[0].keys())
    for r in rows:
        for c in r:
            if c not in cols:
                cols.append(c)
    fmt = lambda v: f"{v:.4g}" if isinstance(v, float) else str(v)
    lines = [",".join(cols)] + [",".join(fmt(r.get(c, "")) for c in cols) for r in rows]
    report(lines, a.csv, a.out)


if __name__ == "__main__":
    main()
