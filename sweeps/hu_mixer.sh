#!/bin/bash
# Hu et al. 2022's vertical mixer (sweeps/hu_mixer.yaml) under the direct force scaling methods: one run per
# method, scale factor and adhesion strength, then the steady-state speed distributions of each adhesion
# strength in one plot (sweeps/plot_speed_pdfs.py) with their table. Each run holds the scene's powder mass
# (count / l^3 particles); a run whose run.h5 is complete (run.done beside it) is skipped when the script is
# started again, and an unfinished one continues from its checkpoint.
#
#   bash sweeps/hu_mixer.sh [--l 4] [--methods hu_method1,hu_method2,hu_method3] [--adhesion capillary|jkr]
#       [--values 0.05] [--count 700000] [--end 0.6] [--from 0.4] [--threads 1] [--reference RUN_LABEL]
#       [--build build] [--out sweeps/results/hu_mixer]
#   bash sweeps/hu_mixer.sh --timing 0.005 [--rounds 3] [--adhesion jkr] [--values 0.1] [--count 700000]
#       [--threads 1] [--build build] [--out sweeps/results/hu_mixer]
#
# --adhesion capillary: the values are surface tensions sigma (N/m), Hu 4.2.1; jkr: surface energies gamma
# (J/m^2) under Hu's simplified JKR (normal: jkr, jkr_separation: contact_loss), Hu 4.2.2; sigma 0 runs the
# dry powder (Hertz-Mindlin, Hu's sigma = 0 curves). --l 1 runs the
# original particles (law none). Outputs: OUT/runs/<method>_l<l>_<adhesion><value>/run.h5 and log.txt,
# OUT/speed_pdf_<adhesion><value>.png and .csv (every run of that value found in OUT/runs, the
# original's as the reference when present), OUT/speed_profiles_<adhesion><value>.png and .csv (the same
# runs' speed and volume share against height and distance from the axis: sweeps/plot_speed_profiles.py);
# each run's cpu.txt holds its pieces' user, system and wall seconds.
#
# --timing SPAN measures the speed-ups instead of running: every finished run of each value (any method and
# l, the original among them) continues from its final checkpoint for SPAN simulated seconds in a scratch
# directory, the runs taking turns for --rounds rounds, so that all of them meet the same machine. Writes
# OUT/speed_<adhesion><value>.csv: per run its particles, steps, the median (min, max) seconds of the time
# loop (the engine's own count: setup and checkpoint reading excluded), the median CPU seconds of the whole
# process, seconds per particle-step and the speed-up against the original (k = 1) from the loop times.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
l=4 methods=hu_method1,hu_method2,hu_method3 adhesion=capillary values=0.05 count=700000 end=0.6 from=0.4
threads=1 build=$root/build out=$root/sweeps/results/hu_mixer timing= rounds=3
while [ $# -gt 0 ]; do
  case "$1" in
    --l) l=$2; shift 2 ;;
    --methods) methods=$2; shift 2 ;;
    --adhesion) adhesion=$2; shift 2 ;;
    --values) values=$2; shift 2 ;;
    --count) count=$2; shift 2 ;;
    --end) end=$2; shift 2 ;;
    --from) from=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --timing) timing=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    -h|--help) sed -n '2,27p' "$0"; exit 0 ;;
    *) echo "hu_mixer.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
cgdem=$build/cgdem
[ -x "$cgdem" ] || { echo "hu_mixer.sh: $cgdem not found: build first (README.md) or give --build DIR" >&2; exit 2; }
case "$adhesion" in capillary|jkr) ;; *) echo "hu_mixer.sh: --adhesion is capillary or jkr" >&2; exit 2 ;; esac
mkdir -p "$out/runs"
scene=$here/hu_mixer.yaml
TIMEFORMAT='%U %S %R'

# The scene overrides of one run: method (none: the original), scale factor l, adhesion value; into args,
# and its particle count into n.
scene_args() {
  local method=$1 l=$2 value=$3
  n=$(/usr/bin/python3 -c "print(round($count / $l ** 3))")
  args=(--set "groups.0.count=$n" --set "output.every=0.01" --threads "$threads")
  [ "$method" != none ] && args+=(--set "groups.0.coarse_grain={law: $method, factor: $l}")
  if [ "$adhesion" = capillary ] && [ "$(/usr/bin/python3 -c "print(float('$value') == 0)")" = True ]; then
    args+=(--set "contact={normal: hertz, tangential: mindlin, wall_adhesion: false}") # Hu's sigma = 0: dry
  elif [ "$adhesion" = capillary ]; then
    args+=(--set "materials.powder.capillary.surface_tension=$value")
  else
    args+=(--set "materials.powder={density: 1000, youngs_modulus: 1.0e8, poisson_ratio: 0.3, restitution: 0.1, friction: 0.3, surface_energy: $value}"
           --set "contact={normal: jkr, jkr_separation: contact_loss, tangential: mindlin, wall_adhesion: false}")
  fi
}

if [ -n "$timing" ]; then
  scratch=$(mktemp -d)
  trap 'rm -rf "$scratch"' EXIT
  for value in ${values//,/ }; do
    runs=()
    for run in "$out"/runs/*_"${adhesion}${value}"; do
      [ -f "$run/run.done" ] && [ -f "$run/run.checkpoint.h5" ] && runs+=("$run")
    done
    [ ${#runs[@]} -gt 0 ] || { echo "hu_mixer.sh: no finished run of $adhesion $value in $out/runs" >&2; exit 2; }
    times=$scratch/times.txt
    : > "$times"
    # Each run's end time: its final checkpoint's time plus the span (read once).
    declare -A until=()
    for run in "${runs[@]}"; do
      until[$run]=$(/usr/bin/python3 -c "import h5py; print(h5py.File('$run/run.checkpoint.h5', 'r').attrs['time'] + $timing)")
    done
    for round in $(seq "$rounds"); do
      for run in "${runs[@]}"; do
        label=$(basename "$run"); label=${label%_"${adhesion}${value}"}
        method=${label%_l*} l=${label##*_l}
        scene_args "$method" "$l" "$value"
        t1=${until[$run]}
        cpu=$( { time "$cgdem" run "$scene" "${args[@]}" --set "time.end=$t1" --restart "$run/run.checkpoint.h5" \
                   --out "$scratch/run.h5" > "$scratch/log.txt" 2>&1; } 2>&1 ) || true
        steps=$(sed -n 's/^done: \([0-9]*\) steps of \([0-9]*\) particles in .*: \([0-9.e+-]*\) particle-steps.*/\1 \2 \3/p' \
                  "$scratch/log.txt")
        [ -n "$steps" ] || { echo "hu_mixer.sh: timing $label failed:" >&2; cat "$scratch/log.txt" >&2; exit 1; }
        echo "$label $steps $cpu" >> "$times"
        echo "hu_mixer.sh: round $round, $label: $steps (steps, particles, particle-steps/s), CPU $cpu (user, sys, wall s)"
      done
    done
    /usr/bin/python3 - "$times" "$out/speed_${adhesion}${value}.csv" <<'PY'
import statistics, sys
rows = {}
for line in open(sys.argv[1]):
    label, steps, particles, rate, user, system, _wall = line.split()
    loop = int(steps) * int(particles) / float(rate)  # the engine's time loop, setup excluded
    rows.setdefault(label, []).append((int(steps), int(particles), loop, float(user) + float(system)))
med = {label: statistics.median(x[2] for x in r) for label, r in rows.items()}
ref = med.get("none_l1")
with open(sys.argv[2], "w") as f:
    f.write("run,particles,steps,loop_s_median,loop_s_min,loop_s_max,cpu_s_median,s_per_particle_step,speedup\n")
    for label, r in sorted(rows.items(), key=lambda kv: -kv[1][0][1]):
        steps, particles = r[0][0], r[0][1]
        loop = [x[2] for x in r]
        cpu = statistics.median(x[3] for x in r)
        speedup = f"{ref / med[label]:.2f}" if ref else ""
        f.write(f"{label},{particles},{steps},{med[label]:.3f},{min(loop):.3f},{max(loop):.3f},{cpu:.2f},"
                f"{med[label] / (steps * particles):.3e},{speedup}\n")
print(open(sys.argv[2]).read(), end="")
PY
  done
  exit 0
fi

[ "$l" = 1 ] && methods=none

for value in ${values//,/ }; do
  for method in ${methods//,/ }; do
    run=$out/runs/${method}_l${l}_${adhesion}${value}
    [ -f "$run/run.done" ] && { echo "hu_mixer.sh: $run done, skipped"; continue; }
    mkdir -p "$run"
    scene_args "$method" "$l" "$value"
    args+=(--set "time.end=$end" --checkpoint-every 0.05 --out "$run/run.h5")
    if [ -f "$run/run.checkpoint.h5" ]; then # continue; the earlier frames stay in run.part<N>.h5
      parts=$(ls "$run" | grep -c '^run\.part[0-9]*\.h5$' || true)
      mv "$run/run.h5" "$run/run.part$((parts + 1)).h5"
      args+=(--restart "$run/run.checkpoint.h5")
    fi
    echo "hu_mixer.sh: $method l = $l, $adhesion $value, $n particles -> $run"
    # Each piece's user, system and wall seconds go to cpu.txt (a piece stopped early too): the speed-ups
    # are taken from CPU time, which other runs sharing the machine do not inflate.
    { time "$cgdem" run "$scene" "${args[@]}" --quiet >> "$run/log.txt" 2>&1; } 2>> "$run/cpu.txt"
    touch "$run/run.done"
  done
  # Every finished run of this adhesion value, the original first (the reference).
  specs=() ref=()
  for run in "$out"/runs/*_"${adhesion}${value}"; do
    [ -f "$run/run.done" ] || continue
    label=$(basename "$run"); label=${label%_"${adhesion}${value}"}
    [[ "$label" == none_l1 ]] && label=original ref=(--reference original)
    for piece in "$run"/run.part*.h5 "$run/run.h5"; do
      [ -f "$piece" ] || continue
      if [ "$label" = original ]; then specs=("$label=$piece" "${specs[@]}"); else specs+=("$label=$piece"); fi
    done
  done
  [ ${#specs[@]} -gt 0 ] && /usr/bin/python3 "$here/plot_speed_pdfs.py" "${specs[@]}" --from "$from" "${ref[@]}" \
    --title "Hu mixer, $adhesion $value, speeds from t = $from s" \
    --out "$out/speed_pdf_${adhesion}${value}.png" --csv "$out/speed_pdf_${adhesion}${value}.csv"
  # Where the runs' speeds differ: speed and volume share against height and distance from the axis.
  [ ${#specs[@]} -gt 0 ] && /usr/bin/python3 "$here/plot_speed_profiles.py" "${specs[@]}" --from "$from" \
    --out "$out/speed_profiles_${adhesion}${value}.png" --csv "$out/speed_profiles_${adhesion}${value}.csv" > /dev/null
done
