#!/usr/bin/env bash
# MPI ranks against OpenMP threads on the settled beds (docs/mpi.md): the same scene as 1 process x T
# threads and as R ranks x 1 thread, runs alternated, medians of particle-steps/s, the share of time in
# MPI communication (of the rank that spent the most), and the largest difference of the last frame from
# the one-process run (the error the ranks cost: round-off). Run on a quiet machine; results in
# perf/README.md ("MPI ranks").
#   perf/mpi/compare.sh [--n 10k|50k|200k] [--scene bed|chute] [--ranks R] [--steps S] [--runs K]
# --scene chute: the bed flowing down a 25-degree slope (perf/peers/bed/compare.sh's chute): lists rebuilt
# every ~17 steps, so each rebuild's redistribution shows in the time.
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
here="$repo/perf/mpi"
bed="$repo/perf/peers/bed"
n=200k scene_kind=bed ranks=2 steps=1000 runs=3
while [ $# -gt 0 ]; do
  case $1 in
    --n) n=$2; shift 2 ;;
    --scene) scene_kind=$2; shift 2 ;;
    --ranks) ranks=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "compare.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
PY=/usr/bin/python3
"$PY" -c 'import h5py, numpy' 2>/dev/null || { echo "compare.sh: needs python3-h5py and python3-numpy (scripts/setup.sh)" >&2; exit 2; }
cgdem="${CGDEM:-$repo/build/cgdem}"
[ -x "$cgdem" ] || bash "$repo/scripts/build.sh"
case $n in
  10k|50k) ;;
  200k) mkdir -p "$bed/work"
        [ -s "$bed/work/settled_bed_200k.csv" ] ||
          "$PY" "$bed/beds.py" tile "$repo/../shared/data/settled_bed_50k.csv" "$bed/work/settled_bed_200k.csv" 2 2 ;;
  *) echo "compare.sh: --n must be 10k, 50k or 200k (got $n)" >&2; exit 2 ;;
esac
scene="$bed/bed_$n.yaml"
case $scene_kind in
  bed) flow=() ;;
  chute) flow=(--set 'gravity=[4.14586, 0, -8.89085]' --set 'groups.0.velocity=[0.5, 0, 0]') ;;
  *) echo "compare.sh: --scene must be bed or chute (got $scene_kind)" >&2; exit 2 ;;
esac
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
end=$(awk -v s="$steps" 'BEGIN { printf "%.10g", s * 1e-5 }')
nproc_=$(nproc)
extra=()
[ "$ranks" -gt "$nproc_" ] && extra=(--oversubscribe --bind-to none)
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $nproc_ cores; $(date -u '+%Y-%m-%d %H:%M'); $scene_kind $n, $steps steps"
printf 'layout\trun\tparticle_steps_per_s\tcommunication_percent\tlist_builds\n' > "$work/rows.tsv"
for run in $(seq "$runs"); do
  "$cgdem" run "$scene" "${flow[@]}" --set time.end="$end" --threads "$ranks" --out "$work/threads.h5" --quiet 2> "$work/t.log"
  rate=$(sed -n 's/^done: .* in .*: \([0-9.e+]*\) particle-steps\/s/\1/p' "$work/t.log")
  builds=$(sed -n 's/.*(\([0-9]*\) list builds).*/\1/p' "$work/t.log")
  printf '1 x %s threads\t%s\t%s\t0\t%s\n' "$ranks" "$run" "$rate" "$builds" >> "$work/rows.tsv"
  mpirun -np "$ranks" "${extra[@]}" "$cgdem" run "$scene" "${flow[@]}" --set time.end="$end" --threads 1 --out "$work/ranks.h5" \
    --quiet 2> "$work/r.log"
  rate=$(sed -n 's/^done: .* in .*: \([0-9.e+]*\) particle-steps\/s/\1/p' "$work/r.log")
  comm=$(sed -n 's/.*MPI communication \([0-9]*\)%.*/\1/p' "$work/r.log")
  builds=$(sed -n 's/.*(\([0-9]*\) list builds).*/\1/p' "$work/r.log")
  printf '%s ranks x 1 thread\t%s\t%s\t%s\t%s\n' "$ranks" "$run" "$rate" "$comm" "$builds" >> "$work/rows.tsv"
done
"$PY" - "$work" <<'EOF'
import sys, h5py, numpy as np
work = sys.argv[1]
rows = [l.rstrip("\n").split("\t") for l in open(f"{work}/rows.tsv")][1:]
for layout in dict.fromkeys(r[0] for r in rows):
    rates = sorted(float(r[2]) for r in rows if r[0] == layout)
    comm = sorted(float(r[3]) for r in rows if r[0] == layout)
    print(f"{layout:>20}: {np.median(rates):.3g} particle-steps/s (runs {', '.join(f'{x:.3g}' for x in rates)}), "
          f"communication {np.median(comm):.0f} % of the time (the rank that spent the most), "
          f"{[r[4] for r in rows if r[0] == layout][-1]} list builds (rank 0)")
a, b = h5py.File(f"{work}/threads.h5"), h5py.File(f"{work}/ranks.h5")
last = sorted(a["frames"].keys())[-1]
assert (a["frames"][last]["id"][:] == b["frames"][last]["id"][:]).all()
for f in ["position", "velocity", "angular_velocity"]:
    d = np.abs(a["frames"][last][f][:] - b["frames"][last][f][:]).max()
    print(f"  last frame, ranks against threads: max |d {f}| = {d:.3g}")
EOF
