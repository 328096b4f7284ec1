#!/usr/bin/env python3
"""Picture of a cgdem result: side and top views of the last frame (coloured by speed) and the
kinetic energy and contact count over time. Usage: plot_results.py RESULTS.h5 OUT.png

The views are drawn to scale (equal aspect) over the domain (read from the scene stored in the result,
when python3-yaml is there; the particles' extent otherwise, and along an axis where they fill less than
half of the domain), and the figure's size follows their aspect ratio: a tall column gets a tall
side view, a long flow a side view across the whole width above the other panels.

Needs Debian's python3-matplotlib, python3-h5py and python3-numpy (run with /usr/bin/python3)."""
import sys

try:
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.collections import EllipseCollection
except ImportError as e:  # the first python3 on PATH may lack Debian's modules
    sys.exit(f"plot_results.py: {e}; run it with /usr/bin/python3 (apt-get install python3-matplotlib python3-h5py)")

VIEW_HEIGHT = 4.5  # inches: the height of a row of panels (a tall side view gets up to TALL_HEIGHT)
TALL_HEIGHT = 9.0
MIN_VIEW, MAX_VIEW = 1.8, 9.0  # inches: the width of a view panel is kept within these
WIDE = 2.0  # a side view wider than this many times its height gets a row of its own


def scene_domain(scene_text):
    """(lo, hi) of the scene's domain, or None when it cannot be read."""
    try:
        import yaml

        d = yaml.safe_load(scene_text)["domain"]
        lo, hi = np.asarray(d["lo"], float), np.asarray(d["hi"], float)
        return (lo, hi) if lo.shape == hi.shape == (3,) and np.all(hi > lo) else None
    except Exception:  # no python3-yaml, or no readable domain: the particles' extent is used
        return None


def view_box(x, r, domain):
    """Per axis, the range drawn (m): the domain where the particles fill at least half of it, else
    the particles' extent; padded by a diameter, and always covering every particle."""
    pad = 2 * r.max()
    lo, hi = x.min(axis=0) - pad, x.max(axis=0) + pad
    if domain is not None:
        for a in range(3):
            length = domain[1][a] - domain[0][a]
            if hi[a] - lo[a] >= 0.5 * length:
                lo[a], hi[a] = min(lo[a], domain[0][a]), max(hi[a], domain[1][a])
    return lo, hi


def panel_width(aspect, height=VIEW_HEIGHT):
    return float(np.clip(height * aspect, MIN_VIEW, MAX_VIEW))


def main(h5_path, png_path):
    with h5py.File(h5_path, "r") as f:
        names = sorted(f["frames"].keys())
        last = f["frames"][names[-1]]
        x = last["position"][:]
        r = last["radius"][:]
        v = last["velocity"][:] if "velocity" in last else np.zeros_like(x)
        t = float(last.attrs["time"])
        series = {k: f["series"][k][:] for k in ("time", "kinetic_energy", "contacts") if k in f["series"]}

        def text(name):
            s = f.attrs.get(name, b"")
            return s.decode() if isinstance(s, bytes) else str(s)

        backend, scene = text("backend"), text("scene")
    speed = np.linalg.norm(v, axis=1)
    lo, hi = view_box(x, r, scene_domain(scene))
    size = hi - lo
    side_aspect, top_aspect = size[0] / size[2], size[0] / size[1]

    # Panel widths from the views' aspect ratios; constrained layout keeps titles and labels apart.
    energy_width = 4.5
    if side_aspect > WIDE:
        # A long, low domain (a runout): the side view across the whole width, the rest below it.
        width = max(panel_width(top_aspect) + energy_width + 1.5, 10.0)
        side_height = float(np.clip(width / side_aspect, 1.5, VIEW_HEIGHT))
        fig = plt.figure(figsize=(width, side_height + VIEW_HEIGHT + 1.2), layout="constrained")
        grid = fig.add_gridspec(2, 2, height_ratios=[side_height, VIEW_HEIGHT],
                                width_ratios=[panel_width(top_aspect), energy_width])
        side, top, energy = fig.add_subplot(grid[0, :]), fig.add_subplot(grid[1, 0]), fig.add_subplot(grid[1, 1])
    else:
        # A tall column (side view at most half as wide as high) gets a taller row, up to TALL_HEIGHT.
        height = float(np.clip(VIEW_HEIGHT * np.sqrt(0.5 / side_aspect), VIEW_HEIGHT, TALL_HEIGHT))
        widths = [panel_width(side_aspect, height), panel_width(top_aspect), energy_width]
        fig = plt.figure(figsize=(sum(widths) + 2.0, height + 1.2), layout="constrained")
        grid = fig.add_gridspec(1, 3, width_ratios=widths)
        side, top, energy = (fig.add_subplot(grid[0, k]) for k in range(3))

    def view(ax, a, b, title, keep):
        # Circles drawn to scale (data units), nearest last so that they stay on top.
        idx = np.nonzero(keep)[0]
        idx = idx[np.argsort(x[idx, 3 - a - b])]
        d = 2e3 * r[idx]
        col = EllipseCollection(d, d, np.zeros_like(d), units="xy", offsets=np.c_[x[idx, a], x[idx, b]] * 1e3,
                                offset_transform=ax.transData, cmap="viridis")
        col.set_array(speed[idx])
        col.set_clim(0, max(speed.max(), 1e-12))
        ax.add_collection(col)
        ax.set_xlim(lo[a] * 1e3, hi[a] * 1e3)
        ax.set_ylim(lo[b] * 1e3, hi[b] * 1e3)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("xyz"[a] + " (mm)")
        ax.set_ylabel("xyz"[b] + " (mm)")
        ax.set_title(title, fontsize=10)
        return col

    # The side view is a slice through the middle so that the profile of a pile or bed shows.
    middle = np.median(x[:, 1])
    half = 3 * r.max()
    slab = np.abs(x[:, 1] - middle) < half
    sc = view(side, 0, 2, f"side view\ny = {middle * 1e3:.3g} ± {half * 1e3:.2g} mm", slab)
    view(top, 0, 1, "top view\nall particles", np.ones(len(r), bool))
    fig.colorbar(sc, ax=[side, top], label="speed (m/s)", shrink=0.8)
    if "time" in series:
        ts, ke = series["time"], series["kinetic_energy"]
        positive = ke > 0  # a start at rest has no place on a log axis
        energy.semilogy(ts[positive], ke[positive], "C0-", label="kinetic energy")
        energy.set_xlabel("time (s)")
        energy.xaxis.set_major_locator(plt.MaxNLocator(5))
        energy.set_ylabel("kinetic energy (J)", color="C0")
        twin = energy.twinx()
        twin.plot(ts, series["contacts"], "C1--", label="contacts")
        twin.set_ylabel("contacts", color="C1")
        energy.set_title("kinetic energy (solid)\nand contacts (dashed)", fontsize=10)
    else:
        energy.set_axis_off()
    fig.suptitle(f"{h5_path.rsplit('/', 1)[-1]}: t = {t:.3g} s, {len(r)} particles"
                 + (f" ({backend})" if backend else ""))
    fig.savefig(png_path, dpi=110)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
