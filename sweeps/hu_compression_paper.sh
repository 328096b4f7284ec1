#!/bin/bash
# Hu et al. 2022's uniaxial compression at the paper's cross-section (sweeps/hu_compression_paper.yaml) in
# Hu's two stages: a pour with friction 0.01, then, continued from its checkpoint, friction 0.3, the cut at
# 50 mm and the piston. One run per method, scale factor and seed of the initial packing; then the table
# and the stress-strain plot of every finished run (sweeps/hu_compression_table.py).
#
#   bash sweeps/hu_compression_paper.sh [--l 2,4] [--methods hu_method1,hu_method2,hu_method3]
#       [--seeds 1,2,3] [--count 102000] [--threads 1] [--build build] [--out sweeps/results/hu_compression_paper]
#
# --l 1 runs the original particles (law none). Each run holds the scene's powder mass (count / l^3
# particles). A finished stage (pour.done, compress.done) is skipped when the script is started again and an
# unfinished one continues from its checkpoint (every 0.1 s of simulated time), so the originals (~1.8 h
# each on one core) can run over several sittings. Outputs: OUT/runs/<method>_l<l>_s<seed>/pour.h5,
# compress.h5 (and compress.partN.h5 from earlier sittings), log.txt and cpu.txt (each piece's user + system
# CPU seconds and wall seconds), OUT/table.md, OUT/summary.csv and OUT/stress_strain.png.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
ls_=2,4 methods=hu_method1,hu_method2,hu_method3 seeds=1,2,3 count=102000 threads=1 build=$root/build
out=$root/sweeps/results/hu_compression_paper
while [ $# -gt 0 ]; do
  case "$1" in
    --l) ls_=$2; shift 2 ;;
    --methods) methods=$2; shift 2 ;;
    --seeds) seeds=$2; shift 2 ;;
    --count) count=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) echo "hu_compression_paper.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
cgdem=$build/cgdem
[ -x "$cgdem" ] || { echo "hu_compression_paper.sh: $cgdem not found: build first (README.md) or give --build DIR" >&2; exit 2; }
scene=$here/hu_compression_paper.yaml
mkdir -p "$out/runs"
TIMEFORMAT='%U %S %R'

# run_stage DIR NAME FROM ARGS...: one stage of one run, from the checkpoint FROM ("-": from the scene's
# start), or from NAME.checkpoint.h5 when an earlier sitting left one (its frames stay in NAME.partN.h5);
# marks NAME.done when it ends.
run_stage() {
  local dir=$1 name=$2 from=$3; shift 3
  [ -f "$dir/$name.done" ] && return 0
  local args=("$@")
  if [ -f "$dir/$name.checkpoint.h5" ]; then
    local parts
    parts=$(ls "$dir" | grep -c "^$name\.part[0-9]*\.h5$" || true)
    [ -f "$dir/$name.h5" ] && mv "$dir/$name.h5" "$dir/$name.part$((parts + 1)).h5"
    from=$dir/$name.checkpoint.h5
  fi
  [ "$from" != - ] && args+=(--restart "$from")
  local t
  t=$({ time "$cgdem" run "$scene" "${args[@]}" --threads "$threads" --checkpoint-every 0.1 \
        --out "$dir/$name.h5" --quiet >> "$dir/log.txt" 2>&1; } 2>&1) ||
    { echo "hu_compression_paper.sh: $dir: $name failed (see $dir/log.txt)" >&2; return 1; }
  echo "$name $t" >> "$dir/cpu.txt"
  touch "$dir/$name.done"
}

for l in ${ls_//,/ }; do
  run_methods=$methods
  [ "$l" = 1 ] && run_methods=none
  n=$(/usr/bin/python3 -c "print(round($count / $l ** 3))")
  for method in ${run_methods//,/ }; do
    for seed in ${seeds//,/ }; do
      dir=$out/runs/${method}_l${l}_s${seed}
      mkdir -p "$dir"
      common=(--set "groups.0.count=$n" --set "groups.0.placement.seed=$seed")
      [ "$method" != none ] && common+=(--set "groups.0.coarse_grain={law: $method, factor: $l}")
      echo "hu_compression_paper.sh: $method l = $l seed $seed, $n particles -> $dir"
      # Stage 1: the pour, friction 0.01, the cut held above the particles, to 0.5 s.
      run_stage "$dir" pour - "${common[@]}" --set materials.glass.friction=0.01 --set time.end=0.5 \
        --set 'outlets.0.point=[0, 0, 0.1299]'
      # Stage 2: the scene as written, from the pour's last step.
      run_stage "$dir" compress "$dir/pour.checkpoint.h5" "${common[@]}"
    done
  done
done
/usr/bin/python3 "$here/hu_compression_table.py" "$out"
