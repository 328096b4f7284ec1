#!/usr/bin/python3
"""Figures of the recipes in docs/recipes.md, from a cgdem result file.

  /usr/bin/python3 scripts/plot_recipe.py collapse column_collapse.h5 column_collapse.png
  /usr/bin/python3 scripts/plot_recipe.py hopper hopper_discharge.h5 hopper_discharge.png [--open 0.45]
  /usr/bin/python3 scripts/plot_recipe.py drum drum_dynamic_angle.h5 drum_dynamic_angle.png
  /usr/bin/python3 scripts/plot_recipe.py heap pour_heap.h5 pour_heap.png

Each writes one PNG (a view of the particles beside the recipe's figures over time) and prints the
recipe's numbers. Needs numpy, h5py and matplotlib (Debian: python3-numpy python3-h5py python3-matplotlib).
"""
import argparse
import math
import sys

try:
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
except ImportError as e:
    sys.exit(f"plot_recipe.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, -numpy, -matplotlib)")

G = 9.81


class Result:
    def __init__(self, path):
        self.f = h5py.File(path, "r")
        self.names = sorted(self.f["frames"].keys())
        # The per-wall groups (wall_force, wall_torque) are not series of their own.
        s = self.f["series"]
        self.series = {k: s[k][()] for k in s.keys() if isinstance(s[k], h5py.Dataset)}

    def frame(self, index):
        g = self.f["frames"][self.names[index]]
        return {k: g[k][()] for k in g.keys()} | {"time": float(g.attrs["time"])}

    def frame_at(self, time):
        times = np.array([self.f["frames"][n].attrs["time"] for n in self.names])
        return self.frame(int(np.argmin(abs(times - time))))


def side_view(ax, frame, horizontal, vertical, depth_axis=None, depth=None, color=None, title=""):
    x = frame["position"]
    keep = np.ones(len(x), bool)
    if depth_axis is not None and depth is not None:
        keep = abs(x[:, depth_axis]) < depth
    r = frame["radius"][keep]
    if isinstance(color, str):
        c = color
    else:
        c = x[keep, vertical] if color is None else color[keep]
    ax.scatter(1e3 * x[keep, horizontal], 1e3 * x[keep, vertical], s=(r / r.max()) * 4, c=c, cmap="viridis",
               linewidths=0)
    ax.set_aspect("equal")
    ax.set_xlabel("xyz"[horizontal] + " (mm)")
    ax.set_ylabel("xyz"[vertical] + " (mm)")
    ax.set_title(title, fontsize=10)


def collapse(res, out, args):
    s = res.series
    t = s["time"]
    name = args.analysis or "collapse"
    before = res.frame_at(args.open - 0.01)
    last = res.frame(len(res.names) - 1)
    fig, axes = plt.subplots(2, 1, figsize=(9, 7.5), constrained_layout=True)
    side_view(axes[0], before, 0, 2, color="0.75")
    side_view(axes[0], last, 0, 2, title=f"column at t = {before['time']:.2f} s (grey) and deposit at "
              f"t = {last['time']:.2f} s (coloured by height)")
    x0 = np.nanmin(s[name][:1])
    h0 = np.nanmax(before["position"][:, 2] + before["radius"])
    runout, height, angle = s[name][-1], s[name + "_height"][-1], s[name + "_angle"][-1]
    ax = axes[1]
    ax.plot(t, 1e3 * s[name + "_front"], label="front position (mm)")
    ax.plot(t, 1e3 * s[name + "_height"], label="height (mm)")
    ax.axvline(args.open, color="grey", ls=":", label="gate lifted")
    ax.set_xlabel("t (s)")
    ax.legend(loc="center right")
    a = h0 / x0
    ax.set_title(f"aspect ratio a = {a:.2f}: runout (L_f - L_0)/L_0 = {(runout - x0) / x0:.2f}, "
                 f"H_f/L_0 = {height / x0:.2f}, deposit angle {angle:.1f} deg", fontsize=10)
    fig.savefig(out, dpi=110)
    print(f"column: L_0 = {1e3 * x0:.1f} mm, H_0 = {1e3 * h0:.1f} mm, a = {a:.2f}")
    print(f"deposit: runout L_f = {1e3 * runout:.1f} mm, (L_f - L_0)/L_0 = {(runout - x0) / x0:.2f}, "
          f"H_f = {1e3 * height:.1f} mm, H_f/L_0 = {height / x0:.2f}, free-surface angle {angle:.1f} deg")
    print(f"Lube et al. (2005), quasi-2D: (L_f - L_0)/L_0 = 1.2 a = {1.2 * a:.2f} (a < 1.8), "
          f"1.9 a^(2/3) = {1.9 * a ** (2 / 3):.2f} (a > 2.8); H_f/L_0 = a^0.4 = {a ** 0.4:.2f} (a > 1.15)")


def hopper(res, out, args):
    s = res.series
    t, m = s["time"], s[args.outlet + "_mass"]
    last = res.frame(len(res.names) - 1)
    density = float(np.median(last["mass"] / (4 / 3 * math.pi * last["radius"] ** 3)))
    d = 2 * float(np.median(last["radius"]))
    # Bulk density of the settled bed just before the gate opens (profile analysis: porosity).
    i_open = int(np.argmin(abs(t - args.open)))
    porosity = s[args.bed][i_open - 1] if args.bed in s else float("nan")
    rho_b = (1 - porosity) * density
    lo, hi = args.open + args.skip, t[-1]
    window = (t >= lo) & (t <= hi)
    slope, intercept = np.polyfit(t[window], m[window], 1)
    residual = m[window] - (slope * t[window] + intercept)
    D = 2 * args.orifice
    bev = {k: args.C * rho_b * math.sqrt(G) * (D - k * d) ** 2.5 for k in (1.4, 1.5, 1.6)}
    C_fit = slope / (rho_b * math.sqrt(G) * (D - 1.5 * d) ** 2.5)
    k_fit = (D - (slope / (args.C * rho_b * math.sqrt(G))) ** 0.4) / d
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.5), constrained_layout=True, width_ratios=[1, 1.3])
    mid = res.frame_at(0.5 * (lo + hi))
    side_view(axes[0], mid, 0, 2, depth_axis=1, depth=2 * d,
              title=f"slice |y| < {2 * d * 1e3:.0f} mm at t = {mid['time']:.2f} s")
    ax = axes[1]
    ax.plot(t, 1e3 * m, "k.", label="mass through the outlet")
    ax.plot(t[window], 1e3 * (slope * t[window] + intercept), "r-", label=f"fit: W = {1e3 * slope:.1f} g/s")
    for k, w in bev.items():
        ax.plot(t[window], 1e3 * (w * (t[window] - lo) + slope * lo + intercept), "--", lw=0.8,
                label=f"Beverloo C = {args.C}, k = {k}: {1e3 * w:.1f} g/s")
    ax.axvline(args.open, color="grey", ls=":", label="gate opens")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("discharged mass (g)")
    ax.legend(fontsize=8)
    ax.set_title(f"orifice D = {1e3 * D:.0f} mm, d = {1e3 * d:.1f} mm, rho_b = {rho_b:.0f} kg/m^3", fontsize=10)
    fig.savefig(out, dpi=110)
    print(f"bed before opening: porosity {porosity:.3f}, bulk density {rho_b:.0f} kg/m^3 "
          f"(particle density {density:.0f})")
    print(f"discharge rate W = {1e3 * slope:.2f} g/s (fit over t = {lo:.2f}-{hi:.2f} s, "
          f"rms residual {1e3 * residual.std():.3f} g)")
    print("Beverloo W = C rho_b sqrt(g) (D - k d)^2.5, C = %.2f: " % args.C +
          ", ".join(f"k = {k}: {1e3 * w:.2f} g/s" for k, w in bev.items()))
    print(f"measured / Beverloo(k = 1.5) = {slope / bev[1.5]:.3f}; fitted C at k = 1.5: {C_fit:.3f}; "
          f"fitted k at C = {args.C}: {k_fit:.2f}")


def drum(res, out, args):
    s = res.series
    t, angle = s["time"], s[args.analysis or "angle"]
    window = t >= args.average_from
    mean, std = float(np.nanmean(angle[window])), float(np.nanstd(angle[window]))
    last = res.frame(len(res.names) - 1)
    fig, axes = plt.subplots(1, 2, figsize=(11, 5), constrained_layout=True)
    v = np.linalg.norm(last["velocity"], axis=1) if "velocity" in last else None
    side_view(axes[0], last, 0, 2, color=v, title=f"t = {last['time']:.2f} s, coloured by speed")
    ax = axes[1]
    ax.plot(t, angle, "k.-", label="free-surface angle")
    ax.axhline(mean, color="r", label=f"mean from {args.average_from} s: {mean:.1f} +- {std:.1f} deg")
    ax.axhspan(mean - std, mean + std, color="r", alpha=0.15)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("angle (deg)")
    ax.set_ylim(0, 60)
    ax.legend()
    fig.savefig(out, dpi=110)
    print(f"dynamic angle of repose: {mean:.2f} +- {std:.2f} deg (mean and standard deviation of "
          f"{int(window.sum())} frames, t = {t[window][0]:.2f}-{t[window][-1]:.2f} s)")


def heap(res, out, args):
    s = res.series
    name = args.analysis or "heap"
    t = s["time"]
    last = res.frame(len(res.names) - 1)
    x = last["position"]
    r = np.hypot(x[:, 0], x[:, 1])
    angle, height, foot = s[name][-1], s[name + "_height"][-1], s[name + "_foot_radius"][-1]
    fig, axes = plt.subplots(1, 2, figsize=(11, 5), constrained_layout=True)
    ax = axes[0]
    ax.scatter(1e3 * r, 1e3 * x[:, 2], s=2, c=x[:, 2], cmap="viridis", linewidths=0)
    rr = np.linspace(0, foot, 10)
    ax.plot(1e3 * rr, 1e3 * math.tan(math.radians(angle)) * (foot - rr), "r-", label=f"fitted flank {angle:.1f} deg")
    ax.set_aspect("equal")
    ax.set_xlabel("distance from the axis (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_title(f"heap at t = {last['time']:.2f} s, all azimuths", fontsize=10)
    ax.legend()
    ax = axes[1]
    ax.plot(t, s[name], "k.-", label="angle of repose (deg)")
    ax.plot(t, 1e3 * s[name + "_height"], "b.-", label="height (mm)")
    ax2 = ax.twinx()
    ax2.plot(t, s["particles"], "g-", label="particles in the domain")
    if args.outlet + "_count" in s:
        ax2.plot(t, s[args.outlet + "_count"], "g--", label="particles spilled")
    ax.set_xlabel("t (s)")
    ax.legend(loc="upper left")
    ax2.legend(loc="lower right")
    fig.savefig(out, dpi=110)
    print(f"heap: angle of repose {angle:.1f} deg (r2 {s[name + '_r2'][-1]:.3f}, {int(s[name + '_bins'][-1])} bins), "
          f"height {1e3 * height:.1f} mm, foot radius {1e3 * foot:.1f} mm; "
          f"{int(s['particles'][-1])} particles on the disk")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("recipe", choices=["collapse", "hopper", "drum", "heap"])
    p.add_argument("result", help="cgdem HDF5 result")
    p.add_argument("png", help="figure to write")
    p.add_argument("--analysis", help="name of the recipe's analysis (default: the recipe scene's)")
    p.add_argument("--open", type=float, default=None, help="time the gate opens (collapse 0.25, hopper 0.45)")
    p.add_argument("--skip", type=float, default=0.15, help="hopper: transient after opening left out of the fit (s)")
    p.add_argument("--orifice", type=float, default=0.006, help="hopper: orifice radius (m)")
    p.add_argument("--C", type=float, default=0.58, help="hopper: Beverloo's discharge coefficient")
    p.add_argument("--bed", default="bed", help="hopper: the profile analysis measuring the bed's porosity")
    p.add_argument("--outlet", default=None, help="series prefix of the outlet (outlet_<name>)")
    p.add_argument("--average-from", type=float, default=0.7, help="drum: average the angle from this time (s)")
    args = p.parse_args()
    if args.open is None:
        args.open = {"collapse": 0.25, "hopper": 0.45}.get(args.recipe, 0.0)
    if args.outlet is None:
        args.outlet = {"hopper": "outlet_drain", "heap": "outlet_spill"}.get(args.recipe, "")
    {"collapse": collapse, "hopper": hopper, "drum": drum, "heap": heap}[args.recipe](Result(args.result), args.png, args)


if __name__ == "__main__":
    main()
