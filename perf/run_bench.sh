#!/usr/bin/env bash
# Engine benchmark on the shared settled beds at 1 and 2 OpenMP threads (and Serial), one process per
# thread count because OpenMP cannot be resized inside a process. Prints particle-steps per second,
# the time split and bytes per particle; run on a quiet machine.
#   perf/run_bench.sh [benchmark filter, e.g. '/10/' or '/50/|/200/']
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bench="${BENCH:-$repo/build/perf/bench_settled_bed}"
[ -x "$bench" ] || bash "$repo/scripts/build.sh"
filter=${1:-.}
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%Y-%m-%d)"
for threads in 1 2; do
  OMP_PROC_BIND=spread OMP_PLACES=threads "$bench" --kokkos-threads=$threads --benchmark_filter="$filter" \
    --benchmark_counters_tabular=true 2>/dev/null | grep -E '^BM_|Benchmark'
done
"$bench" --kokkos-threads=1 --backend=serial --benchmark_filter="$filter" --benchmark_counters_tabular=true 2>/dev/null \
  | grep -E '^BM_'
