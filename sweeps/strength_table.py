#!/usr/bin/python3
"""The strength table of a Thakur compression sweep (sweeps/thakur_periodic.yaml, thakur_paper_depth.yaml)
from its records: per law, the seeds, the CPU speed-up against the originals' mean CPU time, the peak
confined stress (`consolidation`), the unconfined strength (`ucs`, the peak of the reload) and the stress at
the run's end (`stress`), each as mean +- seed sd, with the error against the originals' mean and the
scatter sqrt(sd^2 + sd_orig^2) / orig mean (run_pieces.combined_scatter), and whether the
error lies within it. Stresses in kPa. Prints a Markdown table.

    /usr/bin/python3 sweeps/strength_table.py sweeps/results/thakur_depth_case2
"""
import argparse
import os
import re
import statistics

from run_pieces import combined_scatter, read_record, record_value

METRICS = [("consolidation", "peak confined stress"), ("ucs", "unconfined strength"),
           ("stress", "stress at the run's end")]


def mean_sd(values):
    return statistics.mean(values), statistics.stdev(values) if len(values) > 1 else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sweep_dir")
    a = ap.parse_args()
    records = os.path.join(a.sweep_dir, "records")
    runs = {}
    for name in sorted(os.listdir(records)):
        m = re.fullmatch(r"(.+?)(?:_k[\d.]+)?_s(\d+)\.txt", name)
        if not m:
            continue
        path = os.path.join(records, name)
        if read_record(path).get("status") != "ok":
            continue
        runs.setdefault(m.group(1), []).append(path)
    if "reference" not in runs:
        raise SystemExit(f"strength_table.py: no finished reference run in {records}")

    def values(law, metric):
        return [record_value(p, metric) * 1e-3 for p in runs[law]]

    ref_cpu = statistics.mean(float(read_record(p)["cpu_time_s"]) for p in runs["reference"])
    print("| run | seeds | particles | CPU speed-up | " + " | ".join(f"{label} (kPa) | error (scatter)"
                                                         for _, label in METRICS) + " |")
    print("|---" * (4 + 2 * len(METRICS)) + "|")
    for law in ["reference"] + sorted(k for k in runs if k != "reference"):
        paths = runs[law]
        cpu = statistics.mean(float(read_record(p)["cpu_time_s"]) for p in paths)
        cells = [law, str(len(paths)), read_record(paths[0])["particles"], f"{ref_cpu / cpu:.2f}"]
        for metric, _ in METRICS:
            ref_mean, ref_sd = mean_sd(values("reference", metric))
            mean, sd = mean_sd(values(law, metric))
            cells.append(f"{mean:.2f} +- {sd:.2f}")
            if law == "reference":
                cells.append("-")
                continue
            error = (mean - ref_mean) / ref_mean
            scatter = combined_scatter(sd, ref_sd, ref_mean)
            verdict = "within" if abs(error) <= scatter else "beyond"
            cells.append(f"{100 * error:+.1f} % ({100 * scatter:.1f} %) {verdict}")
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
