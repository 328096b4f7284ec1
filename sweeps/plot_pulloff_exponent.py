#!/usr/bin/python3
"""What the coarse contacts' pull-off force does to Chen's two bulk cases: the pile's height
(results/chen_repose_paper*, records) and the drum's dynamic angle at 10 rpm (results/chen_drum_paper_10rpm*,
the per-frame angles of drum_surface.py averaged over 1.5-7.5 s) against the exponent of F_c ~ k^n at k = 2
(Chen's and Bond's laws 3, Cohesion-number scaling 2.6, Chen's law with surface_energy_power 1: 2), each
seed a point, the original a line; the cohesionless drum beside it.

    /usr/bin/python3 sweeps/plot_pulloff_exponent.py [--results sweeps/results] [--out FILE.png]
"""
import argparse
import csv
import os
import re
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.exit(f"plot_pulloff_exponent.py: {e}; run it with /usr/bin/python3 (Debian's python3-matplotlib)")
from run_pieces import record_value

# (results directory, run name prefix) -> (label, exponent of F_c in k)
PILE = [("chen_repose_paper", "chen_elliott", "Chen's law", 3.0), ("chen_repose_paper", "bond", "Bond", 3.0),
        ("chen_repose_paper", "cohesion", "Cohesion number", 2.6),
        ("chen_repose_paper_gamma_k", "chen_elliott", "Chen's law, gamma ~ k", 2.0)]
DRUM = [("chen_drum_paper_10rpm/angles.csv", "chen_elliott_k2", "Chen's law", 3.0),
        ("chen_drum_paper_10rpm/angles.csv", "bond_k2", "Bond", 3.0),
        ("chen_drum_paper_10rpm/angles.csv", "cohesion_k2", "Cohesion number", 2.6),
        ("chen_drum_paper_10rpm/variants.csv", "chen_elliott_gamma_k_k2", "Chen's law, gamma ~ k", 2.0)]
COLOURS = {"Chen's law": "tab:blue", "Bond": "tab:orange", "Cohesion number": "tab:green",
           "Chen's law, gamma ~ k": "tab:purple"}


def pile_heights(results, directory, prefix, k="_k2"):
    d = os.path.join(results, directory, "records")
    return [record_value(os.path.join(d, f), "repose_height") * 1e3 for f in sorted(os.listdir(d))
            if re.fullmatch(prefix + k + r"_s\d+\.txt", f)]


def window_means(path, prefix, t0=1.5, t1=7.5):
    """Per run whose name is prefix_s<N> (or exactly prefix): the mean angle over frames in [t0, t1]."""
    sums = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            run, t, a = row["run"], float(row["time"]), float(row["angle_deg"])
            if re.fullmatch(re.escape(prefix) + r"(_s\d+)?", run) and t0 - 1e-9 <= t <= t1 + 1e-9 and a == a:
                s = sums.setdefault(run, [0.0, 0])
                s[0] += a
                s[1] += 1
    return [s[0] / s[1] for _, s in sorted(sums.items())]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "results"))
    ap.add_argument("--out", default="pulloff_exponent.png")
    a = ap.parse_args()
    fig, (pile, drum) = plt.subplots(1, 2, figsize=(11, 4.6))
    originals = pile_heights(a.results, "chen_repose_paper", "reference", k="")
    original = sum(originals) / len(originals)
    pile.axhline(original, color="k", lw=1.5,
                 label=f"original, 40,000 ({original:.2f} mm, mean of {len(originals)} seeds)")
    for directory, prefix, label, n in PILE:
        h = pile_heights(a.results, directory, prefix)
        x = n + (0.04 if label == "Bond" else 0.0)
        pile.plot([x] * len(h), h, "o", color=COLOURS[label], alpha=0.6)
        pile.errorbar(x, sum(h) / len(h), fmt="_", ms=22, mew=2.5, color=COLOURS[label], label=f"{label}, 5,000")
        print(f"pile {label}: heights {', '.join(f'{v:.1f}' for v in h)} mm")
    pile.set(xlabel="pull-off force F_c ~ k^n at k = 2: n", ylabel="pile height (mm)",
             title="Chen's pile (Table 5), height at 6.4 s")
    ref_angles = window_means(os.path.join(a.results, "chen_drum_paper_10rpm", "angles.csv"), "reference")
    ref_angle = sum(ref_angles) / len(ref_angles)
    drum.axhline(ref_angle, color="k", lw=1.5,
                 label=f"original, 17,675 ({ref_angle:.1f} deg, mean of {len(ref_angles)} seeds)")
    for path, prefix, label, n in DRUM:
        angles = window_means(os.path.join(a.results, path), prefix)
        x = n + (0.04 if label == "Bond" else 0.0)
        drum.plot([x] * len(angles), angles, "o", color=COLOURS[label], alpha=0.6)
        drum.errorbar(x, sum(angles) / len(angles), fmt="_", ms=22, mew=2.5, color=COLOURS[label],
                      label=f"{label}, 2,209")
        print(f"drum {label}: angles {', '.join(f'{v:.2f}' for v in angles)} deg")
    dry = os.path.join(a.results, "chen_drum_paper_10rpm_cohesionless", "angles.csv")
    dry_ref, dry_coarse = window_means(dry, "reference")[0], window_means(dry, "chen_elliott_k2")
    drum.plot([1.5] * len(dry_coarse), dry_coarse, "s", color="tab:gray", alpha=0.7,
              label="no cohesion: Chen's law, 2,209")
    drum.plot([1.5], [dry_ref], "*", ms=12, color="k", label=f"no cohesion: original ({dry_ref:.1f} deg)")
    print(f"drum without cohesion: original {dry_ref:.2f}, coarse {', '.join(f'{v:.2f}' for v in dry_coarse)} deg")
    drum.set(xlabel="pull-off force F_c ~ k^n at k = 2: n (1.5: no cohesion)",
             ylabel="dynamic angle, mean over 1.5-7.5 s (deg)", title="Chen's drum, 10 rpm, fill 0.14")
    for ax in (pile, drum):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
