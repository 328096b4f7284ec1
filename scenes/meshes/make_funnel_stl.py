#!/usr/bin/python3
"""Writes scenes/meshes/funnel.stl: a conical funnel as a CAD part would come, an ASCII STL in millimetres (the
scene reads it with scale: 0.001). Outlet radius 4 mm at z = 0, widening at 45 degrees to radius 20 mm at
z = 16 mm, `segments` facets around (each a quadrilateral cut into two triangles).

    /usr/bin/python3 scenes/meshes/make_funnel_stl.py [--segments 48] [OUT.stl]
"""
import argparse
import math
import os


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", nargs="?", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "funnel.stl"))
    ap.add_argument("--segments", type=int, default=48)
    a = ap.parse_args()
    r0, r1, h = 4.0, 20.0, 16.0

    def at(r, z, i):
        t = 2 * math.pi * i / a.segments
        return (r * math.cos(t), r * math.sin(t), z)

    with open(a.out, "w") as f:
        f.write("solid funnel\n")
        for i in range(a.segments):
            p00, p01 = at(r0, 0, i), at(r0, 0, i + 1)
            p10, p11 = at(r1, h, i), at(r1, h, i + 1)
            for tri in ((p00, p01, p11), (p00, p11, p10)):
                f.write("facet normal 0 0 0\n outer loop\n")
                for v in tri:
                    f.write(f"  vertex {v[0]:.6f} {v[1]:.6f} {v[2]:.6f}\n")
                f.write(" endloop\nendfacet\n")
        f.write("endsolid funnel\n")
    print(f"make_funnel_stl.py: wrote {a.out} ({2 * a.segments} triangles)")


if __name__ == "__main__":
    main()
