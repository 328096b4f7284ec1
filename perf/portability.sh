#!/usr/bin/env bash
# Portability experiment: one scene on every backend and thread count this build has (Serial; OpenMP with
# 1 and 2 threads; CUDA when 'cgdem info' lists it), printing per backend the particle-steps per second and
# the largest difference of positions and velocities from the Serial run after the same steps. cgdem's
# force accumulation is deterministic (docs/design.md), so zero is the expected difference, not a tolerance.
#   perf/portability.sh [SCENE.yaml] [--set key=value ...]
# Default: scenes/pile_in_cylinder.yaml to 0.3 s (3000 beads poured into a cylinder: contacts form and
# break, walls, rolling resistance, list rebuilds; 23,330 steps).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
cgdem="${CGDEM:-$repo/build/cgdem}"
[ -x "$cgdem" ] || bash "$repo/scripts/build.sh"
py=/usr/bin/python3
"$py" -c 'import h5py, numpy' 2>/dev/null || { echo "portability.sh: needs Debian's python3-h5py and python3-numpy for $py" >&2; exit 2; }

scene="$repo/scenes/pile_in_cylinder.yaml"
overrides=(--set time.end=0.3)
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then scene=$1; shift; overrides=(); fi
overrides+=("$@")

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
backends=$("$cgdem" info | sed -n 's/^backends: //p')
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%Y-%m-%d); cgdem info: $backends"
echo "scene: $scene ${overrides[*]:-}"

runs=("serial 1")
case "$backends" in *openmp*) runs+=("openmp 1" "openmp 2") ;; esac
case "$backends" in *cuda*) runs+=("cuda 1") ;; esac

for r in "${runs[@]}"; do
  set -- $r
  "$cgdem" run "$scene" "${overrides[@]}" --backend "$1" --threads "$2" --quiet --out "$work/$1_$2.h5" \
    > "$work/$1_$2.log" 2>&1 || { cat "$work/$1_$2.log" >&2; exit 1; }
done

"$py" - "$work" "${runs[@]}" <<'EOF'
import re, sys, h5py, numpy as np
work, runs = sys.argv[1], [r.replace(" ", "_") for r in sys.argv[2:]]

def last_frame(name):
    with h5py.File(f"{work}/{name}.h5", "r") as f:
        fr = f["frames"][sorted(f["frames"].keys())[-1]]
        order = np.argsort(fr["id"][:])  # compare particle by particle, whatever the storage order
        return int(fr.attrs["step"]), fr["position"][:][order], fr["velocity"][:][order]

def rate(name):
    m = re.search(r"done: (\d+) steps of (\d+) particles in ([\d.e+-]+) s: ([\d.e+-]+) particle-steps/s",
                  open(f"{work}/{name}.log").read())
    return float(m.group(4)) if m else float("nan")

step0, x0, v0 = last_frame(runs[0])
print(f"| backend | threads | particle-steps/s | steps compared | max abs dx (m) | max abs dv (m/s) | bitwise |")
print("|---|---|---|---|---|---|---|")
for name in runs:
    step, x, v = last_frame(name)
    dx, dv = np.abs(x - x0).max(), np.abs(v - v0).max()
    same = step == step0 and np.array_equal(x, x0) and np.array_equal(v, v0)
    b, t = name.split("_")
    print(f"| {b} | {t} | {rate(name):.3g} | {step} | {dx:.3g} | {dv:.3g} | {'yes' if same else 'NO'} |")
EOF
