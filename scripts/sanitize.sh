#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (GCC, -DCGDEM_SANITIZE=ON) in
# build-asan/, outside CI (several times slower than the Release suite). Any ASan report fails its test, and a
# UBSan report fails its test too (halt_on_error); the counts come from the log. Extra arguments go to ctest
# (e.g. -R CliTest).
#   bash scripts/sanitize.sh            log in build-asan/sanitize.log
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out="$repo/build-asan"
bash "$repo/scripts/setup.sh" >/dev/null
# -O1: each force-law translation unit, instrumented, compiles for tens of minutes at -O2 on this machine.
cmake -S "$repo" -B "$out" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DCGDEM_SANITIZE=ON -DCGDEM_PERF=OFF -DCGDEM_EXCLUDE= >/dev/null
cmake --build "$out" --parallel "${JOBS:-$(nproc)}"
# Leak checking stays on for cgdem and the tests; Kokkos' and TBB's thread pools are not leaks it reports.
# libhdf5's own leaks on a failed close are suppressed (scripts/lsan.supp says why).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:strict_string_checks=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$repo/scripts/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
cd "$out"
status=0
ctest --output-on-failure --timeout 3000 -j "${JOBS:-$(nproc)}" "$@" 2>&1 | tee "$out/sanitize.log" || status=$?
echo "[sanitize] ASan reports: $(grep -c 'ERROR: AddressSanitizer' "$out/sanitize.log" || true)," \
     "leak reports: $(grep -c 'ERROR: LeakSanitizer' "$out/sanitize.log" || true)," \
     "UBSan reports: $(grep -c 'runtime error:' "$out/sanitize.log" || true)"
exit $status
