#!/usr/bin/env python3
"""Energy error of one Hertz collision per integrator, for Hu's periodic-box material (docs/stability.md F1).

Hu's box is dilute (packing fraction ~0.3), so its energy drift is the sum of binary-collision errors.
This integrates a head-on Hertz collision (E 100 MPa, nu 0.3, rho 1000, r 0.25 mm, e = 1) with each
scheme, averaging over 64 phases of the step at which contact starts, and prints the mean relative
kinetic-energy change per collision against dt / T_R. Run: /usr/bin/python3 stability/hu_binary_collision.py
"""
import sys

try:
    import numpy as np
except ImportError:
    sys.exit("needs numpy: run with /usr/bin/python3 (Debian's python3-numpy)")

E, nu, rho, r = 1e8, 0.3, 1000.0, 0.25e-3
m = rho * 4 / 3 * np.pi * r**3
m_eff, E_eff, R_eff = m / 2, E / (2 * (1 - nu**2)), r / 2
T_R = np.pi * r / (0.8766 + 0.163 * nu) * np.sqrt(2 * rho * (1 + nu) / E)


def force(overlap):  # repulsive Hertz force on the relative coordinate
    return np.where(overlap > 0, 4 / 3 * E_eff * np.sqrt(R_eff) * np.maximum(overlap, 0) ** 1.5, 0.0)


def collide(scheme, dt, v0, phases=64):
    """Mean relative energy change of a collision at closing speed v0; gap x < 0 is overlap."""
    x = v0 * dt * (np.arange(phases) + 0.5) / phases
    v = -v0 * np.ones(phases)
    a = force(-x) / m_eff
    for _ in range(1_000_000):
        if scheme == "velocity Verlet":
            v += 0.5 * dt * a
            x += dt * v
            a = force(-x) / m_eff
            v += 0.5 * dt * a
        elif scheme == "symplectic Euler":
            v += dt * force(-x) / m_eff
            x += dt * v
        elif scheme == "forward Euler":
            a = force(-x) / m_eff
            x += dt * v
            v += dt * a
        if np.all(x > 2 * v0 * dt) and np.all(v > 0):
            break
    return (v**2 / v0**2 - 1).mean()


fractions = [0.02, 0.05, 0.1, 0.14, 0.2, 0.3, 0.5]
print("T_R = %.4g s; mean relative energy change per collision at dt / T_R =" % T_R, fractions)
for v0 in (0.5, 1.0, 2.0):
    for scheme in ("velocity Verlet", "symplectic Euler", "forward Euler"):
        row = " ".join("%+.1e" % collide(scheme, f * T_R, v0) for f in fractions)
        print("%.1f m/s  %-17s %s" % (v0, scheme, row))
