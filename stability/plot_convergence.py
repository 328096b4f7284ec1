#!/usr/bin/python3
"""Error against steps per contact for the Hertz and JKR binary impacts (tests/test_stability.cpp output).

usage: plot_convergence.py report_dir out.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

d, png = sys.argv[1], sys.argv[2]
fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
for ax, name, title in ((axes[0], "convergence_hertz.csv", "Hertz (analytic reference)"),
                        (axes[1], "convergence_jkr.csv", "JKR (16x finer reference)")):
    rows = list(csv.DictReader(open(d + "/" + name)))
    n = [float(r["steps_per_contact"]) for r in rows]
    for key, label in (("err_max_overlap", "max overlap"), ("err_contact_time", "contact time"),
                       ("err_restitution", "restitution")):
        ax.loglog(n, [max(float(r[key]), 1e-12) for r in rows], "o-", label=label)
    ax.loglog(n, [n[0] ** 2 * 1e-2 / x ** 2 for x in n], "k:", lw=1, label="slope -2")
    ax.loglog(n, [n[0] * 1e-2 / x for x in n], "k--", lw=1, label="slope -1")
    ax.set_xlabel("steps per Hertz contact time")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8)
axes[0].set_ylabel("relative error")
fig.tight_layout()
fig.savefig(png, dpi=120)
