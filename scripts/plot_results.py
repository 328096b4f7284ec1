#!/usr/bin/env python3
"""Picture of a cgdem result: side and top views of the last frame (coloured by speed) and the
kinetic energy and contact count over time. Usage: plot_results.py RESULTS.h5 OUT.png

Needs Debian's python3-matplotlib, python3-h5py and python3-numpy (run with /usr/bin/python3)."""
import sys

try:
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
except ImportError as e:  # the first python3 on PATH may lack Debian's modules
    sys.exit(f"plot_results.py: {e}; run it with /usr/bin/python3 (apt-get install python3-matplotlib python3-h5py)")


def main(h5_path, png_path):
    with h5py.File(h5_path, "r") as f:
        names = sorted(f["frames"].keys())
        last = f["frames"][names[-1]]
        x = last["position"][:]
        r = last["radius"][:]
        v = last["velocity"][:] if "velocity" in last else np.zeros_like(x)
        t = float(last.attrs["time"])
        series = {k: f["series"][k][:] for k in ("time", "kinetic_energy", "contacts") if k in f["series"]}
        backend = f.attrs.get("backend", b"")
        backend = backend.decode() if isinstance(backend, bytes) else backend
    speed = np.linalg.norm(v, axis=1)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8), gridspec_kw={"width_ratios": [1.3, 1, 1.1]})

    from matplotlib.collections import EllipseCollection

    def view(ax, a, b, label, keep):
        # Circles drawn to scale (data units); the side view is a slice through the middle so the
        # profile of a pile or bed shows, the top view shows everything from above.
        idx = np.nonzero(keep)[0]
        idx = idx[np.argsort(x[idx, 3 - a - b])]
        d = 2e3 * r[idx]
        col = EllipseCollection(d, d, np.zeros_like(d), units="xy", offsets=np.c_[x[idx, a], x[idx, b]] * 1e3,
                                offset_transform=ax.transData, cmap="viridis")
        col.set_array(speed[idx])
        col.set_clim(0, max(speed.max(), 1e-12))
        ax.add_collection(col)
        pad = 2e3 * r.max()
        ax.set_xlim(x[:, a].min() * 1e3 - pad, x[:, a].max() * 1e3 + pad)
        ax.set_ylim(x[:, b].min() * 1e3 - pad, x[:, b].max() * 1e3 + pad)
        ax.set_aspect("equal")
        ax.set_xlabel("xyz"[a] + " (mm)")
        ax.set_ylabel("xyz"[b] + " (mm)")
        ax.set_title(f"{label}, t = {t:.3g} s")
        return col

    middle = np.median(x[:, 1])
    slab = np.abs(x[:, 1] - middle) < 3 * r.max()
    sc = view(axes[0], 0, 2, f"side view, slice |y - {middle * 1e3:.1f} mm| < {3e3 * r.max():.1f} mm", slab)
    view(axes[1], 0, 1, f"top view, all {len(r)} particles", np.ones(len(r), bool))
    fig.colorbar(sc, ax=axes[:2], label="speed (m/s)", shrink=0.8)
    ax = axes[2]
    if "time" in series:
        ax.semilogy(series["time"], np.maximum(series["kinetic_energy"], 1e-30), "C0-", label="kinetic energy (J)")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("kinetic energy (J)")
        ax2 = ax.twinx()
        ax2.plot(series["time"], series["contacts"], "C1--", label="contacts")
        ax2.set_ylabel("contacts")
        ax.set_title(f"energy and contacts ({backend})")
    fig.savefig(png_path, dpi=110, bbox_inches="tight")
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
