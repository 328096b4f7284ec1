#!/usr/bin/env bash
# Fuzzes the scene parser (with --set overrides), the particle file readers (CSV and HDF5) and the checkpoint
# reader with libFuzzer, AddressSanitizer and UndefinedBehaviorSanitizer (clang 14 from Debian), outside CI.
# Builds the targets of tests/fuzz/ into build-fuzz/ (only the sources they need), seeds each corpus from
# scenes/ and from files cgdem writes, then runs each target for RUNS executions (default 1,000,000) or
# MAX_TIME seconds, whichever comes first (default: no time limit).
# Findings land in build-fuzz/findings/<target>/; logs in build-fuzz/<target>.log.
#   bash scripts/fuzz.sh [target ...]      targets: scene particles checkpoint (default: all three)
#   RUNS=200000 bash scripts/fuzz.sh scene
#   MAX_TIME=300 bash scripts/fuzz.sh particles checkpoint
#   FORK=2 bash scripts/fuzz.sh checkpoint  (fuzzing jobs side by side, default 1)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out="$repo/build-fuzz"
runs=${RUNS:-1000000}
max_time=${MAX_TIME:-0}
fork=${FORK:-1}
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene particles checkpoint)

need=()
for p in clang-14 libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  sudo_cmd=()
  [ "$(id -u)" = 0 ] || sudo_cmd=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get -y -q install --no-install-recommends "${need[@]}"
fi
bash "$repo/scripts/setup.sh" >/dev/null # Kokkos headers (core/types.hpp), HDF5, yaml-cpp, TBB

mkdir -p "$out/obj"
kokkos="$repo/third_party/kokkos-install"
flags=(-std=c++17 -g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined -fopenmp
       -I"$repo" -I"$kokkos/include" $(pkg-config --cflags hdf5 2>/dev/null || echo -I/usr/include/hdf5/serial))
sources=(drivers/scene_parser.cpp drivers/particle_generation.cpp drivers/preflight.cpp setup/scaling.cpp
         setup/materials.cpp setup/restitution.cpp core/checkpoint.cpp core/result_writer.cpp
         tests/fuzz/in_process_probe.cpp)
objects=()
for s in "${sources[@]}"; do
  o="$out/obj/$(basename "$s" .cpp).o"
  # Recompiled when the source or any header it includes (listed in the .d file) is newer: an object built
  # against an older layout of the scene structs would make every input crash.
  stale=0
  if [ ! -f "$o" ] || [ ! -f "$o.d" ]; then
    stale=1
  else
    for dep in $(sed -e 's/^[^:]*://' -e 's/\\$//' "$o.d"); do
      if [ ! -e "$dep" ] || [ "$dep" -nt "$o" ]; then stale=1; break; fi
    done
  fi
  if [ "$stale" = 1 ]; then
    echo "[fuzz] compiling $s"
    clang++-14 "${flags[@]}" -MMD -MF "$o.d" -c "$repo/$s" -o "$o"
  fi
  objects+=("$o")
done
libs=(-L"$kokkos/lib" -lkokkoscore -L/usr/lib/x86_64-linux-gnu/hdf5/serial -lhdf5 -lyaml-cpp -ltbb -ldl)

# Seeds: the example scenes (each with one --set line), particle files and a checkpoint cgdem wrote.
seed_dir="$out/seeds"
mkdir -p "$seed_dir/scene" "$seed_dir/particles" "$seed_dir/checkpoint"
for f in "$repo"/scenes/*.yaml; do
  cp "$f" "$seed_dir/scene/"
  { cat "$f"; printf '\n#--set\ngroups.0.count=7\n'; } > "$seed_dir/scene/$(basename "$f" .yaml)_set.yaml"
done
cp "$repo"/tests/fuzz/seeds/*.csv "$seed_dir/particles/" 2>/dev/null || true
if [ -x "$repo/build/cgdem" ] && [ ! -f "$seed_dir/checkpoint/small.checkpoint.h5" ]; then
  tmp=$(mktemp -d)
  "$repo/build/cgdem" run "$repo/scenes/lattice_drop.yaml" --set groups.0.count=8 --set time.end=0.0005 \
    --set output.every=0.0005 --checkpoint-every 0.0005 --out "$tmp/small.h5" --quiet >/dev/null 2>&1 || true
  cp "$tmp/small.checkpoint.h5" "$seed_dir/checkpoint/" 2>/dev/null || true
  cp "$tmp/small.h5" "$seed_dir/particles/" 2>/dev/null || true
  rm -rf "$tmp"
fi

for t in "${targets[@]}"; do
  echo "[fuzz] linking fuzz_$t"
  clang++-14 "${flags[@]}" -fsanitize=fuzzer "$repo/tests/fuzz/fuzz_$t.cpp" "${objects[@]}" "${libs[@]}" \
    -o "$out/fuzz_$t"
  mkdir -p "$out/corpus/$t" "$out/findings/$t"
  # Inputs as long as the largest seed (the HDF5 seeds are tens of kB), at least 4 kB.
  max_len=$(find "$seed_dir/$t" -type f -printf '%s\n' | sort -n | tail -n 1)
  max_len=$(( ${max_len:-0} > 4096 ? max_len : 4096 ))
  echo "[fuzz] fuzz_$t: $runs executions (log $out/$t.log)"
  # Leaks are not findings here: HDF5 and yaml-cpp keep global state. Fork mode: HDF5 inputs are read in
  # this process (tests/fuzz/in_process_probe.cpp), so a crash or hang inside libhdf5 ends one job, is
  # saved as crash-*/timeout-*/oom-* in findings/, and the next job goes on; cgdem's own findings land there too.
  (cd "$out/findings/$t" && ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 \
     "$out/fuzz_$t" -fork="$fork" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
     -runs="$runs" -max_total_time="$max_time" -max_len="$max_len" -timeout=2 -rss_limit_mb=2048 \
     "$out/corpus/$t" "$seed_dir/$t" > "$out/$t.log" 2>&1) || echo "[fuzz] fuzz_$t exited non-zero: see $out/$t.log"
  # The last progress line has the executions, and how many crashes, timeouts and OOMs the jobs ended on.
  grep -E '^#[0-9]+:' "$out/$t.log" | tail -n 1 || true
  echo "[fuzz] findings: $(ls "$out/findings/$t" | wc -l) files in $out/findings/$t"
done
