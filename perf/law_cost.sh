#!/usr/bin/env bash
# The cost of each contact law, and of each direct force scaling around it, relative to Hertz-Mindlin on the
# same settled bed in the same invocation (perf/README.md, "Cohesive laws" and "Direct force scaling").
#
#   perf/law_cost.sh [--n 10k|50k|200k] [--runs R] [--steps S] [--threads "1 2"] [--baseline OTHER_CGDEM]
#                    [LAW ...]
#
# LAW: as perf/peers/bed/laws.sh (hertz, jkr, dmt, capillary, eepa, each optionally @hu_method1, @hu_method2,
# @hu_method3 or @sakai); default: all five laws, and hertz, jkr and capillary under each method. hertz is
# always run. Runs R rounds (default 3) in which every law runs once per thread count, alternating, S steps
# each (default 1000, dt 1e-5 s) on perf/peers/bed/bed_<n>.yaml (default 50k), stepping time only (cgdem's
# "particle-steps/s"). --baseline: a second cgdem executable (e.g. built from an earlier commit) run in the
# same rounds, each law right after the same law of CGDEM, so its rows compare the two binaries.
# Prints per binary, law and thread count the median (min-max) particle-steps/s, its ratio to the same
# binary's Hertz-Mindlin median (the law's cost: Hertz rate / law rate), and the kinetic energy at the end.
# Environment: CGDEM (default build/cgdem). Rows and logs go to perf/peers/bed/work/law-cost-<date>/.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bed=$repo/perf/peers/bed
. "$bed/laws.sh"
CGDEM=${CGDEM:-$repo/build/cgdem}
n=50k runs=3 steps=1000 threads="1 2" baseline="" laws=()
while [ $# -gt 0 ]; do
  case $1 in
    --n) n=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --baseline) baseline=$2; shift 2 ;;
    -h|--help) sed -n 2,17p "$0"; exit 0 ;;
    -*) echo "law_cost.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) laws+=("$1"); shift ;;
  esac
done
[ -f "$bed/bed_$n.yaml" ] || { echo "law_cost.sh: no bed $bed/bed_$n.yaml (--n 10k, 50k or 200k)" >&2; exit 2; }
if [ ${#laws[@]} -eq 0 ]; then
  laws=(jkr dmt capillary eepa)
  for m in hu_method1 hu_method2 hu_method3 sakai; do laws+=("hertz@$m" "jkr@$m" "capillary@$m"); done
fi
laws=(hertz "${laws[@]}")
for law in "${laws[@]}"; do cgdem_law_settings "$law" || { echo "law_cost.sh: unknown law $law" >&2; exit 2; }; done
out=$bed/work/law-cost-$(date +%Y%m%d-%H%M%S)
mkdir -p "$out"
# private copies: a rebuild during the runs changes nothing
bins=(new)
cp "$CGDEM" "$out/cgdem.new"
if [ -n "$baseline" ]; then cp "$baseline" "$out/cgdem.baseline"; bins+=(baseline); fi
end=$(/usr/bin/python3 -c "print($steps * 1e-5)")
echo "law_cost.sh: $(date -u '+%Y-%m-%d %H:%M UTC'), $(lscpu | sed -n 's/^Model name: *//p'), bed $n, $runs rounds x $steps steps, threads $threads" | tee "$out/header.txt"
echo "  new: $CGDEM (sha256 $(sha256sum "$CGDEM" | cut -c1-12))${baseline:+; baseline: $baseline (sha256 $(sha256sum "$baseline" | cut -c1-12))}" | tee -a "$out/header.txt"
printf 'bin\tlaw\tthreads\trun\tpss\tke\n' > "$out/runs.tsv"
seen=" "
for r in $(seq 1 "$runs"); do
  for law in "${laws[@]}"; do
    case $seen in *" $law:$r "*) continue ;; esac   # hertz named twice
    seen="$seen$law:$r "
    cgdem_law_settings "$law"
    for t in $threads; do
      for b in "${bins[@]}"; do
        tag=$out/${b}_${law//@/-}_t${t}_r$r
        "$out/cgdem.$b" run "$bed/bed_$n.yaml" --threads "$t" --quiet --out "$tag.h5" "${CGDEM_LAW[@]}" \
          --set time.end="$end" >"$tag.out" 2>"$tag.log" || { echo "failed: $tag.log" >&2; exit 1; }
        pss=$(sed -n 's/^done: .*: \([0-9.e+]*\) particle-steps\/s.*/\1/p' "$tag.log")
        ke=$(/usr/bin/python3 -c "import h5py; print(f\"{float(h5py.File('$tag.h5', 'r')['series/kinetic_energy'][-1]):.4g}\")")
        rm -f "$tag.h5" "$tag.xdmf"
        printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$b" "$law" "$t" "$r" "$pss" "$ke" >> "$out/runs.tsv"
        printf '  %-8s %-22s x%s run %s: %.3g particle-steps/s, KE %s J\n' "$b" "$law" "$t" "$r" "$pss" "$ke"
      done
    done
  done
done
/usr/bin/python3 - "$out/runs.tsv" <<'PY' | tee "$out/summary.txt"
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
by = {}
for r in rows:
    by.setdefault((r["bin"], r["law"], int(r["threads"])), []).append(r)
med = {k: statistics.median(float(r["pss"]) for r in v) for k, v in by.items()}
print(f"\n{'binary':<9} {'law':<22} {'threads':>7} {'median p-steps/s':>17} {'min - max':>21} {'cost vs hertz':>14} {'KE at end (J)':>16}")
for key in sorted(by, key=lambda k: (k[0] != "new", list(dict.fromkeys(r["law"] for r in rows)).index(k[1]), k[2])):
    pss = [float(r["pss"]) for r in by[key]]
    kes = sorted({r["ke"] for r in by[key]})
    cost = med[(key[0], "hertz", key[2])] / med[key]
    print(f"{key[0]:<9} {key[1]:<22} {key[2]:>7} {med[key]:>17.4g} {min(pss):>10.4g} - {max(pss):<8.4g} {cost:>14.2f} {'/'.join(kes):>16}")
if any(k[0] == "baseline" for k in by):
    print("\nnew / baseline (median particle-steps/s):")
    for key in sorted(k for k in by if k[0] == "new"):
        other = ("baseline",) + key[1:]
        if other in med:
            print(f"  {key[1]:<22} x{key[2]}: {med[key] / med[other]:.2f}")
PY
echo "rows: $out/runs.tsv"
