#!/usr/bin/python3
"""Writes a closed drum as an ASCII STL: a cylinder of radius R and length L along y from y0, tessellated into
`around` segments and `along` rings, closed by two end caps (triangle fans), in metres. The tessellated twin of
a `type: cylinder` wall with `caps: true` for the mesh-versus-analytic cost comparison (perf/mesh/compare.sh).

    /usr/bin/python3 perf/mesh/make_drum_stl.py OUT.stl [--radius 0.042] [--length 0.02] [--y0 -0.01]
        [--around 128] [--along 8]
"""
import argparse
import math


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--radius", type=float, default=0.042)
    ap.add_argument("--length", type=float, default=0.02)
    ap.add_argument("--y0", type=float, default=-0.01)
    ap.add_argument("--around", type=int, default=128)
    ap.add_argument("--along", type=int, default=8)
    a = ap.parse_args()

    def ring(j):
        y = a.y0 + a.length * j / a.along
        return [(a.radius * math.cos(2 * math.pi * i / a.around), y, a.radius * math.sin(2 * math.pi * i / a.around))
                for i in range(a.around)]

    tris = []
    for j in range(a.along):
        lo, hi = ring(j), ring(j + 1)
        for i in range(a.around):
            k = (i + 1) % a.around
            tris.append((lo[i], hi[i], hi[k]))
            tris.append((lo[i], hi[k], lo[k]))
    for j, y in ((0, a.y0), (a.along, a.y0 + a.length)):
        rim = ring(j)
        centre = (0.0, y, 0.0)
        for i in range(a.around):
            tris.append((centre, rim[i], rim[(i + 1) % a.around]))
    with open(a.out, "w") as f:
        f.write("solid drum\n")
        for t in tris:
            f.write("facet normal 0 0 0\n outer loop\n")
            for v in t:
                f.write(f"  vertex {v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")
            f.write(" endloop\nendfacet\n")
        f.write("endsolid drum\n")
    print(f"make_drum_stl.py: wrote {a.out} ({len(tris)} triangles)")


if __name__ == "__main__":
    main()
