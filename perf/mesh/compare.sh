#!/bin/bash
# The cost of a mesh wall against the analytic wall it stands for: perf/mesh/drum.yaml run with its
# analytic cylinder (caps) and with the same drum as a tessellated STL (make_drum_stl.py: 128 segments
# around, 8 along, fans for the caps; 2,304 triangles), alternately, R runs each, same threads.
# Prints each run's particle-steps/s and time split, the medians, and mesh / analytic cost per particle-step.
#   bash perf/mesh/compare.sh [--runs 3] [--threads 1] [--end 0.15]
# Environment: CGDEM (default build/cgdem), OUT (default perf/mesh/work/compare-<date>).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
CGDEM=${CGDEM:-$ROOT/build/cgdem}
RUNS=3
THREADS=1
END=0.15
while [ $# -gt 0 ]; do
  case $1 in
    --runs) RUNS=$2; shift 2 ;;
    --threads) THREADS=$2; shift 2 ;;
    --end) END=$2; shift 2 ;;
    *) echo "compare.sh: unknown option $1 (--runs R, --threads T, --end T)" >&2; exit 2 ;;
  esac
done
[ -x "$CGDEM" ] || { echo "compare.sh: no cgdem executable at $CGDEM (set CGDEM)" >&2; exit 2; }
OUT=${OUT:-$HERE/work/compare-$(date +%Y%m%d-%H%M%S)}
mkdir -p "$OUT"
/usr/bin/python3 "$HERE/make_drum_stl.py" "$OUT/drum.stl"
MESH="walls.0={name: drum, type: mesh, material: powder, file: $OUT/drum.stl, point: [0, -0.01, 0], axis: [0, 1, 0], motion: {rpm: 20, start: 0.05}}"
echo "compare.sh: $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); cgdem at $(cd "$ROOT" && git log -1 --format=%h 2>/dev/null); $RUNS runs x 2 walls, $THREADS thread(s), end $END s"
rates() { sed -n 's/^done: .*: \([0-9.e+]*\) particle-steps\/s.*/\1/p' "$1"; }
for r in $(seq 1 "$RUNS"); do
  for kind in analytic mesh; do
    log=$OUT/$kind-$r.log
    if [ $kind = mesh ]; then extra=(--set "$MESH"); else extra=(); fi
    "$CGDEM" run "$HERE/drum.yaml" --threads "$THREADS" --quiet --out "$OUT/$kind-$r.h5" --set time.end="$END" "${extra[@]}" 2> "$log" ||
      { echo "compare.sh: $kind run $r failed: $log" >&2; exit 1; }
    echo "  $kind run $r: $(rates "$log") particle-steps/s; $(grep -m1 'time split' "$log" | sed 's/^ *//'); $(grep -m1 'final:' "$log" | sed 's/^ *final: //')"
    rm -f "$OUT/$kind-$r.h5" "$OUT/$kind-$r.xdmf"
  done
done
/usr/bin/python3 - "$OUT" "$RUNS" <<'PY'
import re, statistics, sys
out, runs = sys.argv[1], int(sys.argv[2])
med = {}
for kind in ("analytic", "mesh"):
    vals = []
    for r in range(1, runs + 1):
        m = re.search(r"^done: .*: ([0-9.e+]+) particle-steps/s", open(f"{out}/{kind}-{r}.log").read(), re.M)
        vals.append(float(m.group(1)))
    med[kind] = statistics.median(vals)
    print(f"  {kind:8s} median {med[kind]:.3g} particle-steps/s ({', '.join(f'{v:.3g}' for v in vals)})")
print(f"  cost per particle-step, mesh / analytic: {med['analytic'] / med['mesh']:.3f}")
PY
