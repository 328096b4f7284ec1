#!/usr/bin/python3
"""Particle files for the peer comparison of the settled beds (perf/peers/bed).

  beds.py tile  IN.csv OUT.csv NX NY   copy a bed NX x NY times in x and y (shift by the box extent)
  beds.py bottom IN.csv OUT.csv N      keep the N lowest particles (a settled floor layer over the whole
                                       periodic cross-section, so it stays periodic and at rest), ids 1..N
  beds.py data  IN.csv OUT.data [T]    LAMMPS/LIGGGHTS data file (atom_style sphere/granular); T atom types
                                       (default 1; all particles are type 1, a peer input may give the
                                       floor type 2 with parameters of its own, as in.bed.eepa.liggghts)
  beds.py box   IN.csv                 print "xlo xhi ylo yhi zlo zhi" of the bed
  beds.py pair  OUT.data V             two 1 mm spheres, head-on at relative speed V (the impact check)
  beds.py wall  OUT.data V             one 1 mm sphere falling onto the plane z = 0 at speed V (no gravity)

The CSV format is cgdem's (docs/scene_format.md): a comment line with the box, then the header
id,x,y,z,radius[,density]. The first line of the shared beds reads
  # ... box: 0 0.02031 xlo xhi; 0 0.02031 ylo yhi; 0 0.04 zlo zhi; ...
and is the only source of the box. The data files list every atom as
  id type diameter density x y z
which is the Atoms line of both LAMMPS atom_style sphere and LIGGGHTS atom_style granular.
Only the standard library is used so that /usr/bin/python3 runs it anywhere.
"""
import re
import sys


def read_bed(path):
    box = None
    rows = []
    header = None
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            if line.startswith("#"):
                m = re.search(r"box:\s*([-0-9.eE+]+)\s+([-0-9.eE+]+)\s+xlo xhi;\s*([-0-9.eE+]+)\s+([-0-9.eE+]+)\s+ylo yhi;"
                              r"\s*([-0-9.eE+]+)\s+([-0-9.eE+]+)\s+zlo zhi", line)
                if m:
                    box = [float(v) for v in m.groups()]
                continue
            if header is None:
                header = [h.strip() for h in line.split(",")]
                continue
            rows.append(dict(zip(header, (float(v) for v in line.split(",")))))
    if box is None:
        sys.exit(f"{path}: no 'box: ... xlo xhi; ... ylo yhi; ... zlo zhi' comment line")
    for i, r in enumerate(rows):
        r.setdefault("id", i + 1)
        r.setdefault("density", 2500.0)
    return box, rows


def box_comment(box):
    return (f"box: {box[0]!r} {box[1]!r} xlo xhi; {box[2]!r} {box[3]!r} ylo yhi; {box[4]!r} {box[5]!r} zlo zhi; "
            "periodic x and y, floor z=0")


def tile(src, dst, nx, ny):
    box, rows = read_bed(src)
    lx, ly = box[1] - box[0], box[3] - box[2]
    max_id = int(max(r["id"] for r in rows))
    out_box = [box[0], box[0] + nx * lx, box[2], box[2] + ny * ly, box[4], box[5]]
    with open(dst, "w") as f:
        f.write(f"# {src} copied {nx} x {ny} in x and y; {box_comment(out_box)}\n")
        f.write("id,x,y,z,radius,density\n")
        k = 0
        for j in range(ny):
            for i in range(nx):
                for r in rows:
                    f.write(f"{int(r['id']) + k * max_id},{r['x'] + i * lx!r},{r['y'] + j * ly!r},{r['z']!r},"
                            f"{r['radius']!r},{r['density']!r}\n")
                k += 1


def bottom(src, dst, n):
    box, rows = read_bed(src)
    if n > len(rows):
        sys.exit(f"{src} holds {len(rows)} particles, fewer than {n}")
    rows = sorted(rows, key=lambda r: (r["z"], r["id"]))[:n]
    with open(dst, "w") as f:
        f.write(f"# the {n} lowest particles of {src}; {box_comment(box)}\n")
        f.write("id,x,y,z,radius,density\n")
        for i, r in enumerate(rows):
            f.write(f"{i + 1},{r['x']!r},{r['y']!r},{r['z']!r},{r['radius']!r},{r['density']!r}\n")


def write_data(dst, box, atoms, velocities=None, title="cgdem peer comparison", types=1):
    with open(dst, "w") as f:
        f.write(f"{title}\n\n{len(atoms)} atoms\n{types} atom types\n\n")
        f.write(f"{box[0]!r} {box[1]!r} xlo xhi\n{box[2]!r} {box[3]!r} ylo yhi\n{box[4]!r} {box[5]!r} zlo zhi\n\n")
        f.write("Atoms\n\n")
        for a in atoms:
            f.write(f"{int(a['id'])} 1 {2 * a['radius']!r} {a['density']!r} {a['x']!r} {a['y']!r} {a['z']!r}\n")
        if velocities:
            f.write("\nVelocities\n\n")
            for a, v in zip(atoms, velocities):
                f.write(f"{int(a['id'])} {v[0]!r} {v[1]!r} {v[2]!r} 0 0 0\n")


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    cmd = argv[1]
    if cmd == "tile" and len(argv) == 6:
        tile(argv[2], argv[3], int(argv[4]), int(argv[5]))
    elif cmd == "bottom" and len(argv) == 5:
        bottom(argv[2], argv[3], int(argv[4]))
    elif cmd == "data" and len(argv) in (4, 5):
        box, rows = read_bed(argv[2])
        write_data(argv[3], box, rows, title=f"settled bed from {argv[2]}",
                   types=int(argv[4]) if len(argv) == 5 else 1)
    elif cmd == "box" and len(argv) == 3:
        box, _ = read_bed(argv[2])
        print(" ".join(repr(v) for v in box))
    elif cmd == "pair" and len(argv) == 4:
        v = float(argv[3])
        atoms = [dict(id=1, x=-0.00055, y=0.0, z=0.0, radius=0.0005, density=2500.0),
                 dict(id=2, x=0.00055, y=0.0, z=0.0, radius=0.0005, density=2500.0)]
        write_data(argv[2], [-0.005, 0.005, -0.005, 0.005, -0.005, 0.005], atoms,
                   velocities=[(v / 2, 0, 0), (-v / 2, 0, 0)], title="head-on impact of two 1 mm spheres")
    elif cmd == "wall" and len(argv) == 4:
        v = float(argv[3])
        atoms = [dict(id=1, x=0.0, y=0.0, z=0.00055, radius=0.0005, density=2500.0)]
        write_data(argv[2], [-0.005, 0.005, -0.005, 0.005, -0.005, 0.005], atoms,
                   velocities=[(0, 0, -v)], title="one 1 mm sphere falling onto the plane z = 0")
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
