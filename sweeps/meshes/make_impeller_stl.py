#!/usr/bin/python3
"""Writes the three-blade impeller of Hu et al. 2022's vertical mixer (their Fig. 4, a scaled-down Roto Junior
granulator of 84 mm inner diameter) as an ASCII STL in metres, its axis the z axis, its lowest point at z = 0.

Hu give a photograph, not drawings; the dimensions here are assumed from it and from the vessel:
- a hub: a closed cylinder of radius 8 mm and height 16 mm (`--hub-radius`, `--hub-height`), `--facets`
  facets around;
- three flat blades 120 degrees apart, each a closed plate 2 mm thick (`--thickness`) running radially from
  the hub to 40 mm (`--tip-radius`: 2 mm clearance to the 42 mm wall), 12 mm tall (`--blade-height`) and
  pitched 45 degrees (`--pitch`) from the vertical: the blade leans back, its leading face looking forward
  and up, so that turning the impeller counter-clockwise about +z (positive rpm) lifts the powder in front
  of each blade over it, as the blades of a high-shear granulator do; the blade's lower edge sits `--clearance` (1 mm) above the vessel floor.

Each blade and the hub is a closed surface of its own; they overlap where the blades meet the hub, which the
mesh-wall contact handles (each particle meets the nearest face of each part).

    /usr/bin/python3 sweeps/meshes/make_impeller_stl.py sweeps/meshes/impeller.stl
"""
import argparse
import math


def box(centre, axes, half):
    """The 12 triangles of a box centred at `centre` with orthonormal `axes` (3 vectors) and half-extents
    `half`, outward-facing (counter-clockwise seen from outside)."""
    def corner(sx, sy, sz):
        return tuple(centre[d] + sx * half[0] * axes[0][d] + sy * half[1] * axes[1][d] + sz * half[2] * axes[2][d]
                     for d in range(3))
    c = {(sx, sy, sz): corner(sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)}
    quads = [
        [(1, -1, -1), (1, 1, -1), (1, 1, 1), (1, -1, 1)],
        [(-1, -1, -1), (-1, -1, 1), (-1, 1, 1), (-1, 1, -1)],
        [(-1, 1, -1), (-1, 1, 1), (1, 1, 1), (1, 1, -1)],
        [(-1, -1, -1), (1, -1, -1), (1, -1, 1), (-1, -1, 1)],
        [(-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)],
        [(-1, -1, -1), (-1, 1, -1), (1, 1, -1), (1, -1, -1)],
    ]
    tris = []
    for q in quads:
        a, b, cc, d = (c[v] for v in q)
        tris += [(a, b, cc), (a, cc, d)]
    return tris


def cylinder(radius, z0, z1, facets):
    """A closed cylinder about z from z0 to z1, `facets` segments around, end caps as fans."""
    ring = [(radius * math.cos(2 * math.pi * i / facets), radius * math.sin(2 * math.pi * i / facets))
            for i in range(facets)]
    tris = []
    for i in range(facets):
        (x0, y0), (x1, y1) = ring[i], ring[(i + 1) % facets]
        tris += [((x0, y0, z0), (x1, y1, z0), (x1, y1, z1)), ((x0, y0, z0), (x1, y1, z1), (x0, y0, z1))]
        tris += [((0, 0, z1), (x0, y0, z1), (x1, y1, z1)), ((0, 0, z0), (x1, y1, z0), (x0, y0, z0))]
    return tris


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--blades", type=int, default=3)
    ap.add_argument("--hub-radius", type=float, default=0.008)
    ap.add_argument("--hub-height", type=float, default=0.016)
    ap.add_argument("--tip-radius", type=float, default=0.040)
    ap.add_argument("--blade-height", type=float, default=0.012)
    ap.add_argument("--thickness", type=float, default=0.002)
    ap.add_argument("--pitch", type=float, default=45.0, help="blade angle from the vertical, degrees")
    ap.add_argument("--clearance", type=float, default=0.001)
    ap.add_argument("--facets", type=int, default=32)
    a = ap.parse_args()

    pitch = math.radians(a.pitch)
    # The blade's vertical extent and the height of its centre above the floor.
    rise = a.blade_height * math.cos(pitch) + a.thickness * math.sin(pitch)
    zc = a.clearance + 0.5 * rise
    tris = cylinder(a.hub_radius, a.clearance, a.clearance + a.hub_height, a.facets)
    # Radially the blade starts half-way into the hub so that no gap opens where it meets the hub's facets.
    r0 = 0.5 * a.hub_radius
    for b in range(a.blades):
        phi = 2 * math.pi * b / a.blades
        radial = (math.cos(phi), math.sin(phi), 0.0)
        tangential = (-math.sin(phi), math.cos(phi), 0.0)
        # The plate's height direction, tilted from +z towards the trailing side (-tangential), and its
        # thickness direction radial x up (a right-handed frame keeps the box's faces outward): the
        # leading face looks forward and up.
        up = tuple(math.cos(pitch) * (d == 2) - math.sin(pitch) * tangential[d] for d in range(3))
        normal = (radial[1] * up[2] - radial[2] * up[1], radial[2] * up[0] - radial[0] * up[2],
                  radial[0] * up[1] - radial[1] * up[0])
        rc = 0.5 * (r0 + a.tip_radius)
        centre = (rc * radial[0], rc * radial[1], zc)
        tris += box(centre, (radial, up, normal), (0.5 * (a.tip_radius - r0), 0.5 * a.blade_height, 0.5 * a.thickness))
    with open(a.out, "w") as f:
        f.write("solid impeller\n")
        for t in tris:
            f.write("facet normal 0 0 0\n outer loop\n")
            for v in t:
                f.write(f"  vertex {v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")
            f.write(" endloop\nendfacet\n")
        f.write("endsolid impeller\n")
    zmax = max(v[2] for t in tris for v in t)
    print(f"make_impeller_stl.py: wrote {a.out} ({len(tris)} triangles, top at {1e3 * zmax:.2f} mm)")


if __name__ == "__main__":
    main()
