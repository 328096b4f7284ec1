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

    def view(ax, a, b, label):
        order = np.argsort(x[:, 1] if label == "side" else x[:, 2])  # paint far particles first
        # Marker area in points^2 from the radius in data units (approximate, for the axis extent).
        span = max(np.ptp(x[:, a]), np.ptp(x[:, b]), 1e-12)
        size = (r[order] / span * 72 * 4.5) ** 2 * 3.1
        sc = ax.scatter(x[order, a] * 1e3, x[order, b] * 1e3, s=size, c=speed[order], cmap="viridis",
                        edgecolors="none")
        ax.set_aspect("equal")
        ax.set_xlabel("xyz"[a] + " (mm)")
        ax.set_ylabel("xyz"[b] + " (mm)")
        ax.set_title(f"{label} view, t = {t:.3g} s, N = {len(r)}")
        return sc

    sc = view(axes[0], 0, 2, "side")
    view(axes[1], 0, 1, "top")
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
