#!/usr/bin/python3
"""Figures of the coarse-graining validation (docs/coarse_graining.md) from the CSV files that
`build/validation/write_scaling_csv [DIR]` writes into validation/results (or DIR).

    /usr/bin/python3 validation/plot_scaling.py [results_dir]
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "results")
KS = [1.0, 2.0, 4.0]
STYLE = {1.0: dict(color="k", lw=2.2, ls="-"), 2.0: dict(color="tab:blue", lw=1.5, ls="--"),
         4.0: dict(color="tab:red", lw=1.2, ls=":")}


def read(name):
    with open(os.path.join(RESULTS, name)) as f:
        return list(csv.DictReader(f))


def by_law_k(rows):
    out = defaultdict(list)
    for r in rows:
        out[(r["law"], float(r["k"]))].append(r)
    return out


def col(rows, key):
    return [float(r[key]) for r in rows]


def case_a(series, law, fname, title):
    fig, ax = plt.subplots(2, 2, figsize=(10, 7.5))
    for k in KS:
        rows = series.get((law, k), [])
        if not rows:
            continue
        t = [x * 1e3 for x in col(rows, "time")]
        v, d, f = col(rows, "velocity"), [x * 1e6 for x in col(rows, "overlap")], col(rows, "force_over_Fc")
        lab = f"k = {k:g}"
        ax[0, 0].plot(t, v, label=lab, **STYLE[k])
        ax[0, 1].plot(t, f, label=lab, **STYLE[k])
        ax[1, 0].plot(t, d, label=lab, **STYLE[k])
        ax[1, 1].plot(d, f, label=lab, **STYLE[k])
    ax[0, 0].set(xlabel="time from first contact (ms)", ylabel="relative normal velocity / approach speed")
    ax[0, 1].set(xlabel="time from first contact (ms)", ylabel="F / F_c (repulsive > 0)")
    ax[1, 0].set(xlabel="time from first contact (ms)", ylabel="overlap (um)")
    ax[1, 1].set(xlabel="overlap (um)", ylabel="F / F_c")
    for a in ax.flat:
        a.grid(alpha=0.3)
        a.legend()
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, fname), dpi=110)
    plt.close(fig)


def case_b(rows, law, lever, fname, title, torque_power="0"):
    """Chen case b (oblique wall impact): the four panels of the paper's figure."""
    series = defaultdict(list)
    for r in rows:
        if r["law"] == law and r["lever_arm"] == lever and r["torque_power"] == torque_power:
            series[float(r["k"])].append(r)
    if not series:
        return
    fig, ax = plt.subplots(2, 2, figsize=(10, 7.5))
    for k in KS:
        rs = series.get(k, [])
        if not rs:
            continue
        t = [x * 1e9 for x in col(rs, "time")]
        lab = f"k = {k:g}"
        ax[0, 0].plot(t, col(rs, "tangential_stiffness_over_k3"), label=lab, **STYLE[k])
        ax[0, 1].plot(t, col(rs, "tangential_force_over_Fc"), label=lab, **STYLE[k])
        ax[1, 0].plot(t, [x * 1e-6 for x in col(rs, "omega_times_k")], label=lab, **STYLE[k])
        ax[1, 1].plot(t, col(rs, "normal_velocity"), label=f"normal, {lab}", **STYLE[k])
        ax[1, 1].plot(t, col(rs, "tangential_velocity"), label=f"tangential, {lab}", alpha=0.6, **STYLE[k])
    ax[0, 0].set(xlabel="time from first contact (ns)", ylabel="tangential stiffness / k^3 (N/m)")
    ax[0, 1].set(xlabel="time from first contact (ns)", ylabel="tangential force / F_c")
    ax[1, 0].set(xlabel="time from first contact (ns)", ylabel="angular velocity x k (1e6 rad/s)")
    ax[1, 1].set(xlabel="time from first contact (ns)", ylabel="velocity (m/s; normal > 0 approaching)")
    for a in ax.flat:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, fname), dpi=110)
    plt.close(fig)


def case_c(sweep, laws, fname, title):
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.3))
    colors = {"chen_elliott": "k", "bond": "tab:orange", "cohesion": "tab:green", "hu_method1": "tab:purple",
              "hu_method2": "tab:brown", "hu_method3": "tab:pink", "sakai": "tab:cyan"}
    marks = {1.0: "o", 2.0: "s", 4.0: "^"}
    for law in laws:
        for k in KS:
            rows = sweep.get((law, k), [])
            if not rows:
                continue
            v = col(rows, "speed")
            style = dict(color=colors[law], marker=marks[k], ms=5, lw=1, ls="-" if k == 1 else "--",
                         label=f"{law} k={k:g}")
            ax[0].plot(v, col(rows, "restitution"), **style)
            # Stuck impacts have no contact duration or rebound overlap: left out of those panels.
            free = [r for r in rows if r["stuck"] == "0"]
            vf = col(free, "speed")
            ax[1].plot(vf, [x * 1e9 for x in col(free, "contact_time")], **style)
            ax[2].plot(vf, [x * 1e9 for x in col(free, "max_overlap")], **style)
    ax[0].set(xlabel="impact velocity (m/s)", ylabel="effective restitution", xscale="log")
    ax[1].set(xlabel="impact velocity (m/s)", ylabel="contact duration (ns)", xscale="log", yscale="log")
    ax[2].set(xlabel="impact velocity (m/s)", ylabel="max overlap (nm)", xscale="log", yscale="log")
    for a in ax:
        a.grid(alpha=0.3, which="both")
    ax[0].legend(fontsize=7, ncol=2)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, fname), dpi=110)
    plt.close(fig)


def sticking(rows, fname):
    data = defaultdict(list)
    for r in rows:
        data[r["law"]].append((float(r["k"]), float(r["sticking_velocity"])))
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for law, pts in data.items():
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=law)
    ax.set(xlabel="coarse-graining factor k", ylabel="critical sticking velocity (m/s)", yscale="log",
           title="Chen case c: critical sticking velocity against k")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, fname), dpi=110)
    plt.close(fig)


def main():
    series = by_law_k(read("case_a_series.csv"))
    case_a(series, "chen_elliott", "case_a_chen_elliott.png",
           "Chen case a, head-on JKR collision: Chen-Elliott scaling, k = 1, 2, 4")
    for law in ["bond", "cohesion", "hu_method1", "hu_method2", "hu_method3", "sakai"]:
        case_a(series, law, f"case_a_{law}.png", f"Chen case a, head-on JKR collision: {law} scaling, k = 1, 2, 4")
    b = read("case_b_series.csv")
    case_b(b, "chen_elliott", "auto", "case_b_chen_elliott.png",
           "Chen case b, oblique wall impact: Chen-Elliott, lever arm R (the law's, default), k = 1, 2, 4")
    case_b(b, "chen_elliott", "contact_point", "case_b_chen_elliott_contact_point.png",
           "Chen case b: Chen-Elliott with the lever arm R - delta/2, k = 1, 2, 4")
    for law in ["bond", "cohesion", "hu_method1"]:
        case_b(b, law, "auto", f"case_b_{law}.png", f"Chen case b, oblique wall impact: {law}, k = 1, 2, 4")
    case_b(b, "hu_method1", "auto", "case_b_hu_method1_torque3.png",
           "Chen case b: hu_method1 with torques l^3 (coarse_grain.torque_power: 3), l = 1, 2, 4", "3")
    sweep = by_law_k(read("case_c_sweep.csv"))
    case_c(sweep, ["chen_elliott", "bond", "cohesion"], "case_c_parameter_laws.png",
           "Chen case c, 1.27 um particle on a wall: parameter scaling laws")
    case_c(sweep, ["chen_elliott", "hu_method1", "hu_method2", "hu_method3", "sakai"], "case_c_direct_laws.png",
           "Chen case c: direct force scaling methods (Chen-Elliott for reference)")
    sticking(read("sticking_velocity.csv"), "sticking_velocity.png")


if __name__ == "__main__":
    main()
