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
#
# --adhesion capillary: the values are surface tensions sigma (N/m), Hu 4.2.1; jkr: surface energies gamma
# (J/m^2) under Hu's simplified JKR (normal: jkr, jkr_separation: contact_loss), Hu 4.2.2; sigma 0 runs the
# dry powder (Hertz-Mindlin, Hu's sigma = 0 curves). --l 1 runs the
# original particles (law none). Outputs: OUT/runs/<method>_l<l>_<adhesion><value>/run.h5 and log.txt,
# OUT/speed_pdf_<adhesion><value>.png and .csv (every run of that value found in OUT/runs, the
# original's as the reference when present); each run's cpu.txt holds its pieces' user, system and wall
# seconds.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
l=4 methods=hu_method1,hu_method2,hu_method3 adhesion=capillary values=0.05 count=700000 end=0.6 from=0.4
threads=1 build=$root/build out=$root/sweeps/results/hu_mixer
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
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) echo "hu_mixer.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
cgdem=$build/cgdem
[ -x "$cgdem" ] || { echo "hu_mixer.sh: $cgdem not found: build first (README.md) or give --build DIR" >&2; exit 2; }
case "$adhesion" in capillary|jkr) ;; *) echo "hu_mixer.sh: --adhesion is capillary or jkr" >&2; exit 2 ;; esac
mkdir -p "$out/runs"
scene=$here/hu_mixer.yaml
TIMEFORMAT='%U %S %R'

n=$(/usr/bin/python3 -c "print(round($count / $l ** 3))")
[ "$l" = 1 ] && methods=none

for value in ${values//,/ }; do
  for method in ${methods//,/ }; do
    run=$out/runs/${method}_l${l}_${adhesion}${value}
    [ -f "$run/run.done" ] && { echo "hu_mixer.sh: $run done, skipped"; continue; }
    mkdir -p "$run"
    args=(--set "groups.0.count=$n" --set "time.end=$end" --set "output.every=0.01" --threads "$threads"
          --checkpoint-every 0.05 --out "$run/run.h5")
    [ "$method" != none ] && args+=(--set "groups.0.coarse_grain={law: $method, factor: $l}")
    if [ "$adhesion" = capillary ] && [ "$(/usr/bin/python3 -c "print(float('$value') == 0)")" = True ]; then
      args+=(--set "contact={normal: hertz, tangential: mindlin, wall_adhesion: false}") # Hu's sigma = 0: dry
    elif [ "$adhesion" = capillary ]; then
      args+=(--set "materials.powder.capillary.surface_tension=$value")
    else
      args+=(--set "materials.powder={density: 1000, youngs_modulus: 1.0e8, poisson_ratio: 0.3, restitution: 0.1, friction: 0.3, surface_energy: $value}"
             --set "contact={normal: jkr, jkr_separation: contact_loss, tangential: mindlin, wall_adhesion: false}")
    fi
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
done
