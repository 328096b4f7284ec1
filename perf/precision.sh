#!/usr/bin/env bash
# The precision knob's speed against its error: the default build (per-pair contact history stored in
# double) against a CGDEM_FLOAT_FORCES build (stored in float, computed in double;
# positions, velocities and total forces double in both), on the same inputs:
#   speed      median particle-steps/s of R alternating runs on the shared 10k and 50k settled beds (1 thread);
#   bed error  after S steps from the same bed: contacts, kinetic energy, largest position difference
#              (in radii) and velocity difference of any particle (the trajectory divergence);
#   restitution the achieved e of the two-sphere and sphere-wall impacts of perf/peers/bed/impact.
#   perf/precision.sh [--runs R] [--steps S]          (defaults 3 and 1000)
# Environment: DOUBLE (default build/cgdem), FLOAT (default build-float/cgdem, configured and built here
# when missing: cmake -DCGDEM_FLOAT_FORCES=ON).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
runs=3
steps=1000
while [ $# -gt 0 ]; do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    -h|--help) sed -n 2,11p "$0"; exit 0 ;;
    *) echo "precision.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
double_bin=${DOUBLE:-$repo/build/cgdem}
float_bin=${FLOAT:-$repo/build-float/cgdem}
py=/usr/bin/python3
"$py" -c 'import h5py, numpy' 2>/dev/null || { echo "precision.sh: needs Debian's python3-h5py and python3-numpy" >&2; exit 2; }
[ -x "$double_bin" ] || bash "$repo/scripts/build.sh"
if [ ! -x "$float_bin" ]; then
  cmake -S "$repo" -B "$repo/build-float" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCGDEM_FLOAT_FORCES=ON \
    -DCGDEM_TESTS=OFF -DCGDEM_PERF=OFF >/dev/null
  cmake --build "$repo/build-float" --target cgdem --parallel "$(nproc)"
  float_bin=$repo/build-float/cgdem
fi
"$float_bin" info | grep -q 'history float' || { echo "precision.sh: $float_bin is not a float-forces build" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bed_dir=$repo/perf/peers/bed
end=$("$py" -c "print($steps * 1e-5)")
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC'); load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "$runs alternating runs x $steps steps per bed, 1 thread; double: $double_bin; float: $float_bin"

rate() { sed -n 's/^done: .*: \([0-9.e+]*\) particle-steps\/s.*/\1/p' "$1"; }
for n in 10k 50k; do
  for r in $(seq 1 "$runs"); do
    for p in double float; do
      bin=$double_bin; [ $p = float ] && bin=$float_bin
      "$bin" run "$bed_dir/bed_$n.yaml" --threads 1 --quiet --set time.end="$end" --out "$work/${p}_$n.h5" \
        >/dev/null 2>"$work/${p}_${n}_$r.log" || { cat "$work/${p}_${n}_$r.log" >&2; exit 1; }
      echo "$n $p $r $(rate "$work/${p}_${n}_$r.log")" >> "$work/rates.txt"
    done
  done
done

for geometry in pair wall; do
  scene=impact.yaml; [ $geometry = wall ] && scene=wall.yaml
  for p in double float; do
    bin=$double_bin; [ $p = float ] && bin=$float_bin
    "$bin" run "$bed_dir/impact/$scene" --threads 1 --quiet --out "$work/${p}_$geometry.h5" >/dev/null 2>&1
  done
done

"$py" - "$work" <<'EOF'
import statistics, sys
import h5py
import numpy as np

work = sys.argv[1]
rates = {}
for line in open(f"{work}/rates.txt"):
    n, p, r, v = line.split()
    rates.setdefault((n, p), []).append(float(v))

def last_frame(path):
    f = h5py.File(path, "r")
    g = f["frames"][sorted(f["frames"].keys())[-1]]
    order = np.argsort(g["id"][:])
    return {k: g[k][:][order] for k in ("position", "velocity", "radius")}, f["series"]

print()
print("| bed | double p-steps/s (min-max) | float p-steps/s (min-max) | float / double | contacts double / float "
      "| kinetic energy double (J), float rel. diff | max dx (radii) | max dv (m/s) |")
print("|---|---|---|---|---|---|---|---|")
for n in ("10k", "50k"):
    d, f = rates[(n, "double")], rates[(n, "float")]
    fd, sd = last_frame(f"{work}/double_{n}.h5")
    ff, sf = last_frame(f"{work}/float_{n}.h5")
    dx = np.abs(fd["position"] - ff["position"]).max(axis=1) / fd["radius"]
    dv = np.abs(fd["velocity"] - ff["velocity"]).max()
    print(f"| {n} | {statistics.median(d):.3g} ({min(d):.3g}-{max(d):.3g}) | {statistics.median(f):.3g} "
          f"({min(f):.3g}-{max(f):.3g}) | {statistics.median(f) / statistics.median(d):.3f} | "
          f"{int(sd['contacts'][-1])} / {int(sf['contacts'][-1])} | {sd['kinetic_energy'][-1]:.6g}, "
          f"{sf['kinetic_energy'][-1] / sd['kinetic_energy'][-1] - 1:+.1e} | {dx.max():.2e} | {dv:.2e} |")

def restitution(path, geometry):
    fr, _ = last_frame(path)
    v = fr["velocity"]
    return (v[1, 0] - v[0, 0]) / 0.5 if geometry == "pair" else v[0, 2] / 0.5

print()
print("| impact (0.5 m/s, dt 1e-5 s) | e double | e float | difference |")
print("|---|---|---|---|")
for geometry in ("pair", "wall"):
    ed = restitution(f"{work}/double_{geometry}.h5", geometry)
    ef = restitution(f"{work}/float_{geometry}.h5", geometry)
    print(f"| {geometry} | {ed:.9f} | {ef:.9f} | {ef - ed:.2e} |")
EOF
