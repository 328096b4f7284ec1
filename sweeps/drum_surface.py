#!/usr/bin/python3
"""The dynamic angle of every run of a drum sweep, from its saved frames: the bed's free-surface angle of
each frame as the engine's `drum_angle` analysis computes it (evaluated again by `cgdem analyse` over the
run's frames, so that a run recorded with another method or other parameters is read the same way), its
mean and standard deviation over a time window, and each law's mean over the seeds against the reference's.

    /usr/bin/python3 sweeps/drum_surface.py SWEEP_DIR --scene sweeps/chen_drum_paper.yaml --from 1.5 --to 7.5 \\
        [--fit-fraction 0.6] [--cell-factor 4] [--wall-layer 1.5] [--bed-fraction 0.2] \\
        [--png angle_time.png] [--csv angles.csv] [--frames-png cross_sections.png --at 2 4 7]

Reads SWEEP_DIR/runs/<run>/run.part<N>.h5 then run.h5 (a run continued from checkpoints) of every run with a
record in SWEEP_DIR/records (a finished run). The analysis is the run's own first `drum_angle` (the scene
stored in its result file) with the options below set on it; --scene gives the drum's size for the layer
figure and the cross-sections. Besides the angle it reports the mass fraction above the drum's axis
(powder stuck to the wall and carried over the top, the analysis' `_carried`). --cell-factor, --wall-layer,
--bed-fraction and --fit-fraction are the analysis' cell_width (in largest radii), wall_layer, bed_fraction
and fit_fraction, to show how much of an angle is the method's. The cgdem executable: $CGDEM, else the
repository's build/cgdem, else `cgdem` on the PATH.
"""
import argparse
import math
import os
import re
import sys

try:
    import h5py
    import numpy as np
    import yaml
except ImportError as e:  # the interpreter first on PATH may lack them; Debian's /usr/bin/python3 has them
    sys.exit(f"drum_surface.py: {e}; run it with /usr/bin/python3 (Debian's python3-h5py, -numpy, -yaml)")
from run_pieces import analyse, analysis_of, combined_scatter, run_pieces, stored_scene


def drum_of(scene_path):
    scene = yaml.safe_load(open(scene_path))
    analysis = next(a for a in scene.get("analyses", []) if a.get("type") == "drum_angle")
    wall = next(w for w in scene["walls"] if w["name"] == analysis["drum"])
    axis = np.array(wall["axis"], float)
    axis /= np.linalg.norm(axis)
    g = np.array(scene["gravity"], float)
    up = -(g - g.dot(axis) * axis)
    up /= np.linalg.norm(up)
    return np.array(wall["point"], float), axis, up, float(wall["radius"]), float(wall.get("length", 0)), bool(wall.get("caps", False))


def layer_per_carried_fraction(rad, drum):
    """The factor that turns the carried mass fraction into a layer on the wall above the axis (the upper
    half of the shell and of the caps), in particle diameters: the same for two sizes when each keeps the
    same number of particle layers on the wall."""
    _, _, _, radius, length, caps = drum
    area = math.pi * radius * length + (math.pi * radius**2 if caps else 0.0)
    volume = (4.0 / 3.0 * math.pi * rad**3).sum()
    return volume / area / (2 * rad.max()) if area > 0 else float("nan")


def run_series(rundir, drum, cell_factor=4.0, wall_layer=1.5, bed_fraction=0.2, fit_fraction=0.6):
    """Every frame's time, angle, carried mass fraction and layer (diameters) of the run in `rundir`:
    `cgdem analyse` over its pieces with its own first drum_angle analysis and these parameters."""
    files = run_pieces(rundir)
    with h5py.File(files[0], "r") as f:
        rad = f["frames"][sorted(f["frames"])[0]]["radius"][:]
    index, spec = analysis_of(stored_scene(files[0]), "drum_angle")
    name = spec.get("name", "drum_angle")
    rows = analyse(files, [f"analyses.{index}.{key}={value!r}" for key, value in
                           (("cell_width", float(cell_factor * rad.max())), ("wall_layer", wall_layer),
                            ("bed_fraction", bed_fraction), ("fit_fraction", fit_fraction))])
    carried = rows[name + "_carried"]
    return np.round(rows["time"], 9), rows[name], carried, carried * layer_per_carried_fraction(rad, drum)


def frame_at(rundir, t_at):
    """The positions, radii and time of the saved frame nearest t_at (the last piece holding it)."""
    best = None
    for fn in run_pieces(rundir):
        with h5py.File(fn, "r") as f:
            for name in f["frames"]:
                t = float(f["frames"][name].attrs["time"])
                if best is None or abs(t - t_at) <= abs(best[0] - t_at):
                    best = (t, fn, name)
    t, fn, name = best
    with h5py.File(fn, "r") as f:
        return f["frames"][name]["position"][:], f["frames"][name]["radius"][:], t


def law_of(run):
    return "reference" if run.startswith("reference") else re.sub(r"_s\d+$", "", run)


def summary(values):
    v = np.array(values)
    return v.mean(), v.std(ddof=1) if len(v) > 1 else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sweep_dir")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--from", dest="t0", type=float, required=True, help="start of the averaging window (s)")
    ap.add_argument("--to", dest="t1", type=float, default=float("inf"))
    ap.add_argument("--fit-fraction", type=float, default=0.6)
    ap.add_argument("--cell-factor", type=float, default=4.0, help="cell width in largest radii")
    ap.add_argument("--wall-layer", type=float, default=1.5, help="dropped wall layer in cells")
    ap.add_argument("--bed-fraction", type=float, default=0.2, help="solid fraction of a bed cell")
    ap.add_argument("--png", help="angle and carried mass against time of every run (window shaded)")
    ap.add_argument("--csv", help="every frame's angle and carried mass fraction of every run")
    ap.add_argument("--frames-png", help="cross-sections of the reference and each law's first seed at --at")
    ap.add_argument("--at", type=float, nargs="+", default=[3.0], help="times (s) of --frames-png")
    ap.add_argument("--title", help="title of --png (default: the sweep directory's name)")
    a = ap.parse_args()
    drum = drum_of(a.scene)
    kw = dict(cell_factor=a.cell_factor, wall_layer=a.wall_layer, bed_fraction=a.bed_fraction, fit_fraction=a.fit_fraction)
    # The finished runs: those with a record (a run still going, or killed, has frames but no record).
    records = os.path.join(a.sweep_dir, "records")
    runs = sorted(d for d in os.listdir(os.path.join(a.sweep_dir, "runs"))
                  if not d.startswith(".") and (not os.path.isdir(records) or os.path.exists(os.path.join(records, d + ".txt"))))
    series = {r: run_series(os.path.join(a.sweep_dir, "runs", r), drum, **kw) for r in runs}
    print(f"window {a.t0}-{a.t1} s; cell {a.cell_factor} radii, wall layer {a.wall_layer} cells, "
          f"bed fraction {a.bed_fraction}, fit fraction {a.fit_fraction}")
    print("run, frames, mean angle (deg), its std over the window, fitless frames, mean mass fraction above "
          "the axis, as a layer on the wall (diameters)")
    per_run = {}
    for r in runs:
        t, ang, car, lay = series[r]
        w = (t >= a.t0) & (t <= a.t1)
        ok = w & np.isfinite(ang)
        mean, std = summary(ang[ok]) if ok.any() else (float("nan"), float("nan"))
        per_run[r] = (mean, car[w].mean())
        print(f"{r}, {w.sum()}, {mean:.2f}, {std:.2f}, {(w & ~np.isfinite(ang)).sum()}, {car[w].mean():.3f}, "
              f"{lay[w].mean():.3f}")
    laws = {}
    for r in runs:
        laws.setdefault(law_of(r), []).append(per_run[r])
    reference = laws.get("reference", [(float("nan"), float("nan"))])  # nan errors until a reference is done
    (ref_angle, ref_sd), ref_carried = summary([x[0] for x in reference]), summary([x[1] for x in reference])[0]
    print("law, seeds, angle mean over seeds (deg), seed sd, error, scatter (sqrt(sd^2 + reference sd^2) / "
          "reference), within, carried mean, seed sd, error")
    for law, vals in laws.items():
        am, asd = summary([x[0] for x in vals])
        cm, csd = summary([x[1] for x in vals])
        error, scatter = (am - ref_angle) / ref_angle, combined_scatter(asd, ref_sd, ref_angle)
        print(f"{law}, {len(vals)}, {am:.2f}, {asd:.2f}, {100 * error:+.1f} %, {100 * scatter:.1f} %, "
              f"{'yes' if abs(error) <= scatter else 'no'}, {cm:.3f}, {csd:.3f}, "
              f"{100 * (cm - ref_carried) / ref_carried:+.0f} %")
    if a.csv:
        with open(a.csv, "w") as out:
            out.write("run,time,angle_deg,mass_fraction_above_axis,layer_above_axis_diameters\n")
            for r in runs:
                for t, ang, car, lay in zip(*series[r]):
                    out.write(f"{r},{t:.6g},{ang:.6g},{car:.6g},{lay:.6g}\n")
    if a.png or a.frames_png:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    if a.png:
        fig, ax = plt.subplots(2, 1, figsize=(10, 8), sharex=True)
        for r in runs:
            t, ang, car, _ = series[r]
            ref_run = law_of(r) == "reference"
            style = dict(color="black" if ref_run else None, lw=1.6 if ref_run else 0.8, label=r)
            ax[0].plot(t, ang, **style)
            ax[1].plot(t, car, **style)
        for x in ax:
            x.axvspan(a.t0, min(a.t1, max(s[0].max() for s in series.values())), color="0.9", zorder=0)
        ax[0].set_ylabel("bed surface angle (deg)")
        ax[1].set_ylabel("mass fraction above the axis")
        ax[1].set_xlabel("time (s)")
        ax[0].set_title((a.title or os.path.basename(os.path.normpath(a.sweep_dir))) + ": averaging window shaded")
        ax[0].legend(fontsize=7, ncol=2)
        fig.tight_layout()
        fig.savefig(a.png, dpi=110)
    if a.frames_png:
        shown = [r for r in runs if law_of(r) == "reference"][:1]
        shown += [next(r for r in runs if law_of(r) == law) for law in laws if law != "reference"]
        center, axis, up, radius = drum[:4]
        eu = np.cross(up, axis)
        fig, ax = plt.subplots(len(a.at), len(shown), figsize=(3.2 * len(shown), 3.2 * len(a.at)), squeeze=False)
        for j, r in enumerate(shown):
            times, angles, fractions, _ = series[r]
            for i, t_at in enumerate(a.at):
                pos, rad, t = frame_at(os.path.join(a.sweep_dir, "runs", r), t_at)
                k = int(np.argmin(np.abs(times - t)))
                d = pos - center
                x = ax[i][j]
                points_per_mm = 2.9 * 72 / (2.1e3 * radius)  # a panel ~2.9 inches across 2.1 drum radii
                x.scatter(1e3 * (d @ eu), 1e3 * (d @ up), s=(2e3 * rad * points_per_mm) ** 2, lw=0, color="C0")
                x.add_patch(plt.Circle((0, 0), 1e3 * radius, fill=False, color="0.4"))
                x.set_title(f"{r}, t = {t:.2f} s\nangle {angles[k]:.1f} deg, above axis {fractions[k]:.2f}", fontsize=8)
                x.set_xlim(-1.05e3 * radius, 1.05e3 * radius)
                x.set_ylim(-1.05e3 * radius, 1.05e3 * radius)
                x.set_aspect("equal")
                x.set_xticks([])
                x.set_yticks([])
        fig.tight_layout()
        fig.savefig(a.frames_png, dpi=110)


if __name__ == "__main__":
    main()
