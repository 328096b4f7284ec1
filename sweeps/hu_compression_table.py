#!/usr/bin/python3
"""Table and stress-strain plot of Hu's compression at the paper's size, from its sweep's run files
(sweeps/hu_compression_paper.yaml, `cgdem sweep ... --seeds --first-stage ...`).

    /usr/bin/python3 sweeps/hu_compression_table.py OUT [--strains 0.05,0.1] [--against OTHER --against-label L]

Reads every run of OUT/records (status ok): the piston's stress against strain from
OUT/runs/<run>/run*.h5 (/series/stress, /series/stress_strain; pieces of several sittings pooled), the
particle count after the cut, and the run's CPU seconds (both stages) from its record. The curves go to
OUT/curves.csv (committed, the run files are not), which stands in for a run whose files are gone; a run
with neither gives its record's final point only (the stress at strain 0.1). Per method and scale
factor over the seeds: the stress at each strain (mean +- standard deviation), its error against the
originals' mean, the scatter (the seed-to-seed standard deviations of both, combined: sqrt(sd^2 +
sd_orig^2) / orig mean) and whether the error lies within it, and the speed-up in CPU time against the
originals' mean. Writes OUT/table.md, OUT/table.csv and OUT/stress_strain.png (one panel per method, Hu's
Fig. 3: the originals against l = 2 and 4, each the mean curve over its seeds with its min-max band).
With --against OTHER (the same runs under another protocol, e.g. another piston speed): the change of
each (method, l)'s stress at the last strain against OTHER's, with both seed scatters combined.
"""
import argparse
import glob
import os
import sys

try:
    import h5py
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:  # the interpreter first on PATH may lack them; Debian's /usr/bin/python3 has them
    sys.exit(f"hu_compression_table.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, python3-matplotlib)")
from run_pieces import combined_scatter, read_record, run_pieces

NAMES = {"none": "original", "hu_method1": "Method 1", "hu_method2": "Method 2", "hu_method3": "Method 3"}


def stress_at(strain, stress, e):
    """The stress at strain e: interpolated on a curve, or a lone final point's own if it lies at e; a
    strain within 1e-9 of a curve's end counts as on it (the piston's last position is e to round-off)."""
    if len(strain) == 1:
        return stress[0] if abs(strain[0] - e) < 1e-9 else np.nan
    e = min(max(e, strain[0]), strain[-1]) if strain[0] - 1e-9 <= e <= strain[-1] + 1e-9 else e
    return np.interp(e, strain, stress, left=np.nan, right=np.nan)


def read_curves_csv(path):
    """run -> (strain, stress) from an earlier curves.csv."""
    curves = {}
    if os.path.exists(path):
        with open(path) as f:
            next(f)
            for line in f:
                run, _, _, e, sigma = line.rstrip("\n").split(",")
                curves.setdefault(run, ([], []))
                curves[run][0].append(float(e))
                curves[run][1].append(float(sigma))
    return {run: (np.array(e), np.array(sigma)) for run, (e, sigma) in curves.items()}


def read_run(d):
    """Strain and stress over the compression (pieces of several sittings pooled) and the particles; None
    when the run's files are gone."""
    t, strain, stress = [], [], []
    particles = None
    pieces = run_pieces(d)  # the compression stage's pieces (its first stage is the filling)
    if not pieces:
        return None
    for path in pieces:
        with h5py.File(path, "r") as f:
            s = f["series"]
            for a, b, c in zip(s["time"][:], s["stress_strain"][:], s["stress"][:]):
                if t and a <= t[-1] + 1e-9:
                    continue  # a continuation repeats its checkpoint's frame
                t.append(a)
                strain.append(b)
                stress.append(c)
            particles = int(s["particles"][-1])
    strain, stress = np.array(strain), np.array(stress)
    ok = np.isfinite(strain)
    return strain[ok], stress[ok], particles


def read_runs(out):
    """(law, l) -> [(run, (strain, stress, particles, CPU s))] over OUT/records, and the curves found."""
    kept = read_curves_csv(os.path.join(out, "curves.csv"))
    runs, curves = {}, {}
    for path in sorted(glob.glob(os.path.join(out, "records", "*.txt"))):
        rec = read_record(path)
        if rec.get("status") != "ok":
            continue
        name = os.path.basename(path)[: -len(".txt")]
        law, k = rec["law"], int(round(float(rec["k"])))
        values = {line.split()[1]: float(line.split()[2]) for line in open(path) if line.startswith("value ")}
        particles = int(values.get("particles", rec["particles"]))
        found = read_run(os.path.join(out, "runs", name))
        if found is not None:
            strain, stress, particles = found
            curves[name] = (law, k, strain, stress)
        elif name in kept:
            strain, stress = kept[name]
            curves[name] = (law, k, strain, stress)
        else:  # the final point alone: an interpolation finds it at exactly its strain
            strain, stress = np.array([values["stress_strain"]]), np.array([values["stress"]])
        runs.setdefault((law, k), []).append((name, (strain, stress, particles, float(rec["cpu_time_s"]))))
    return runs, curves


def statistics(runs, strains):
    """Per (law, l): seeds, mean particles and CPU s, and the stress's mean and sd over the seeds at each
    strain (over the seeds that reach it)."""
    stats = {}
    for key, seeds in runs.items():
        at = np.array([[stress_at(r[0], r[1], e) for e in strains] for _, r in seeds])
        have = np.isfinite(at).sum(axis=0)  # seeds with a value at each strain
        stats[key] = {
            "seeds": len(seeds),
            "particles": int(np.mean([r[2] for _, r in seeds])),
            "cpu": float(np.mean([r[3] for _, r in seeds])),
            "have": have,
            "mean": np.array([np.nanmean(at[:, i]) if have[i] else np.nan for i in range(len(strains))]),
            "sd": np.array([np.nanstd(at[:, i], ddof=1) if have[i] > 1 else np.nan for i in range(len(strains))]),
        }
    return stats


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--strains", default="0.05,0.1")
    ap.add_argument("--against", help="another sweep of the same runs (e.g. another piston speed): the change "
                    "of each stress at the last strain against it, with the two seed scatters combined")
    ap.add_argument("--against-label", default="against", help="what --against is, for the column names")
    ap.add_argument("--title", default="Hu's compression, 14 x 14 mm, 50 mm bed: mean over seeds, min-max band")
    a = ap.parse_args()
    strains = [float(x) for x in a.strains.split(",")]
    runs, curves = read_runs(a.out)
    if not runs:
        sys.exit(f"hu_compression_table.py: no finished run in {a.out}/records")
    with open(os.path.join(a.out, "curves.csv"), "w") as f:
        f.write("run,law,l,strain,stress\n")
        for name, (law, k, strain, stress) in sorted(curves.items()):
            for e, sigma in zip(strain, stress):
                f.write(f"{name},{law},{k},{e:.6g},{sigma:.6g}\n")

    stats = statistics(runs, strains)
    other = statistics(read_runs(a.against)[0], strains[-1:]) if a.against else {}
    ref = stats.get(("none", 1))
    order = sorted(stats, key=lambda k: (k[0] != "none", k[0], k[1]))
    header = ["method", "l", "seeds", "particles", "CPU s per run", "speed-up (CPU)"]
    for e in strains:
        header += [f"stress at {e:g} (Pa)", "error", "scatter", "within"]
    if other:
        header += [f"stress at {strains[-1]:g}, {a.against_label} (Pa)", "change", "scatter"]
    rows = []
    for key in order:
        s = stats[key]
        row = [NAMES.get(key[0], key[0]), str(key[1]), str(s["seeds"]), f"{s['particles']:,}", f"{s['cpu']:.0f}"]
        row.append(f"{ref['cpu'] / s['cpu']:.1f}" if ref else "")
        for i in range(len(strains)):
            if not s["have"][i]:
                row += ["(curve not kept)", "", "", ""]
                continue
            row.append(f"{s['mean'][i]:.4g} +- {s['sd'][i]:.2g}" if s["have"][i] > 1 else f"{s['mean'][i]:.4g}")
            if ref and key != ("none", 1) and ref["have"][i]:
                err = s["mean"][i] / ref["mean"][i] - 1
                sd_r = ref["sd"][i] if ref["have"][i] > 1 else 0.0
                scatter = combined_scatter(s["sd"][i], sd_r, ref["mean"][i])
                within = "yes" if abs(err) <= scatter else "no"
                row += [f"{100 * err:+.1f} %", f"{100 * scatter:.1f} %", within]
            else:
                row += ["", "", ""]
        if other:
            o = other.get(key)
            if o is None or not o["have"][0]:
                row += ["", "", ""]
            else:
                change = s["mean"][-1] / o["mean"][0] - 1
                scatter = combined_scatter(s["sd"][-1], o["sd"][0], o["mean"][0])
                row += [f"{o['mean'][0]:.4g} +- {o['sd'][0]:.2g}", f"{100 * change:+.1f} %", f"{100 * scatter:.1f} %"]
        rows.append(row)
    with open(os.path.join(a.out, "table.csv"), "w") as f:
        f.write(",".join(h.replace(",", "") for h in header) + "\n")
        for r in rows:
            f.write(",".join(c.replace(",", "") for c in r) + "\n")
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("| " + " | ".join(header) + " |\n|" + "---|" * len(header) + "\n")
        for r in rows:
            f.write("| " + " | ".join(r) + " |\n")
    print(open(os.path.join(a.out, "table.md")).read(), end="")

    methods = sorted({k[0] for k in stats if k[0] != "none"})
    fig, axes = plt.subplots(1, max(1, len(methods)), figsize=(4.2 * max(1, len(methods)), 3.8), squeeze=False)
    grid = np.linspace(0, max(strains) * 1.1, 120)
    colours = {1: "k", 2: "tab:blue", 4: "tab:orange", 8: "tab:green"}
    for ax, method in zip(axes[0], methods or ["none"]):
        for key in [("none", 1)] + sorted(k for k in stats if k[0] == method):
            if key not in runs:
                continue
            label = "original" if key[0] == "none" else f"l = {key[1]}"
            c = colours.get(key[1], None)
            whole = [r for _, r in runs[key] if len(r[0]) > 1]
            if not whole:  # only the records' final points: their mean and min-max at the last strain
                e = max(strains)
                points = np.array([stress_at(r[0], r[1], e) for _, r in runs[key]]) / 1e3
                ax.errorbar([e], [points.mean()], yerr=[[points.mean() - points.min()], [points.max() - points.mean()]],
                            fmt="o", color=c, capsize=3, label=f"{label} ({len(points)} seeds, final point)")
                continue
            curves = np.array([np.interp(grid, r[0], r[1], left=np.nan, right=np.nan) for r in whole])
            ax.plot(grid, curves.mean(axis=0) / 1e3, color=c, label=f"{label} ({len(curves)} seeds)")
            if len(curves) > 1:
                ax.fill_between(grid, curves.min(axis=0) / 1e3, curves.max(axis=0) / 1e3, color=c, alpha=0.2, lw=0)
        ax.set_title(NAMES.get(method, method))
        ax.set_xlabel("strain")
        ax.set_ylabel("piston stress (kPa)")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "stress_strain.png"), dpi=110)
    print(f"hu_compression_table.py: wrote {a.out}/table.md, table.csv, curves.csv and stress_strain.png")


if __name__ == "__main__":
    main()
