#!/bin/bash
# Side-by-side timing of cgdem, LIGGGHTS and LAMMPS on the shared settled beds (perf/peers/README.md).
#
#   compare.sh [--n 2k|10k|50k|200k|all] [--law hertz|jkr|dmt|capillary|eepa] [--scene bed|chute]
#              [--runs R] [--steps S] [--codes "cgdem liggghts lammps"] [--out DIR]
#
# --scene: bed (default) the settled bed at rest under gravity; chute, the same bed flowing: gravity tilted
# 25 degrees about y (an inclined plane, periodic along the slope) and every particle started at 0.5 m/s
# down the slope, so that the floor shears the bed from below, contacts open and close throughout, and the
# neighbour list is rebuilt every few tens of steps (each code's count is in its log).
# --law: the contact law of all codes (default hertz, Hertz-Mindlin). jkr: full JKR with surface energy GAMMA
# (default 0.05 J/m^2), bonds broken at the pull-off force as LAMMPS does (cgdem: jkr_separation pull_off);
# dmt: Hertz-Mindlin plus DMT adhesion. The floor is not adhesive (in.bed.lammps says why). Both run against
# LAMMPS (LIGGGHTS 3.8 has neither: its sjkr cohesion is a different law). capillary (Hertz-Mindlin with
# water bridges, liquid fraction 0.00415) and eepa (linear EEPA, k1 100, k2 300, k_adh 50 N/m, f0 -5e-6 N)
# run against LIGGGHTS (in.bed.capillary.liggghts, in.bed.eepa.liggghts: what is matched and what is not).
#
# For each bed size: cgdem with 1 and 2 threads, LIGGGHTS and LAMMPS with mpirun -np 1 and -np 2, run
# alternately (R rounds of all six, default 3), S steps each (default 2000, dt 1e-5 s). Setup is excluded:
# cgdem's "particle-steps/s" summary times the stepping only, the peers' rate is atoms x steps / "Loop time".
# Every code writes the same output, the first and the last frame with every particle field (cgdem its HDF5
# frames, the peers a binary dump, deleted after the run), so the times and the peak memory include the same I/O.
# Prints per code and thread/rank count the median and min-max of particle-steps/s, the peak memory per
# particle (/usr/bin/time max RSS summed over ranks / N, whole process: includes the executable and
# libraries), the contacts per particle at the end ((particle-particle + floor contacts) / N, cgdem's count
# in /series/contacts), the kinetic energy at the end (cgdem's /series/kinetic_energy, the peers' thermo ke),
# the ratios cgdem / peer at 1 and 2 threads/ranks and each code's 2-vs-1 speed-up (of the medians, and run
# by run).
# Raw rows and logs go to DIR (default perf/peers/bed/work/compare-<date>/, git-ignored).
# Environment: CGDEM (default build/cgdem), LIGGGHTS (liggghts), LMP (lmp), MPIRUN (mpirun),
# MPIRUN_FLAGS (added to mpirun; --allow-run-as-root is added when running as root), LAMMPS_E (the LAMMPS
# restitution input from impact/impact.sh, default 0.86212), GAMMA (surface energy of --law jkr and dmt).
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
SHARED_DATA=$(cd "$HERE/../../../../shared/data" && pwd)   # ../shared beside the repo
ROOT=$(cd "$HERE/../../.." && pwd)
CGDEM=${CGDEM:-$ROOT/build/cgdem}
LIGGGHTS=${LIGGGHTS:-liggghts}
LMP=${LMP:-lmp}
MPIRUN=${MPIRUN:-mpirun}
LAMMPS_E=${LAMMPS_E:-0.86212}
PY=/usr/bin/python3
SIZES=10k
RUNS=3
STEPS=2000
CODES=""
LAW=hertz
SCENE=bed
GAMMA=${GAMMA:-0.05}
OUT=""
CORES=$(getconf _NPROCESSORS_ONLN)
while [ $# -gt 0 ]; do
  case $1 in
    --n) SIZES=$2; shift 2 ;;
    --runs) RUNS=$2; shift 2 ;;
    --steps) STEPS=$2; shift 2 ;;
    --codes) CODES=$2; shift 2 ;;
    --law) LAW=$2; shift 2 ;;
    --scene) SCENE=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    -h|--help) sed -n 2,32p "$0"; exit 0 ;;
    *) echo "compare.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
[ "$SIZES" = all ] && SIZES="2k 10k 50k 200k"
# The law as cgdem's --set overrides of bed_*.yaml (the peers take it as -var law).
# shellcheck source=laws.sh
. "$HERE/laws.sh"
cgdem_law_settings "$LAW" "$GAMMA" && case $LAW in hertz|jkr|dmt|capillary|eepa) ;; *) false ;; esac ||
  { echo "compare.sh: --law must be hertz, jkr, dmt, capillary or eepa (got $LAW)" >&2; exit 2; }
case $LAW in
  hertz) [ -n "$CODES" ] || CODES="cgdem liggghts lammps" ;;
  jkr|dmt) [ -n "$CODES" ] || CODES="cgdem lammps" ;;
  capillary|eepa) [ -n "$CODES" ] || CODES="cgdem liggghts" ;;
esac
case " $CODES " in *" liggghts "*) case $LAW in hertz|capillary|eepa) ;; *) echo "compare.sh: LIGGGHTS runs --law hertz, capillary or eepa" >&2; exit 2 ;; esac ;; esac
case " $CODES " in *" lammps "*) case $LAW in hertz|jkr|dmt) ;; *) echo "compare.sh: LAMMPS runs --law hertz, jkr or dmt" >&2; exit 2 ;; esac ;; esac
# The scene as cgdem's --set overrides and the peers' -var (their inputs default to the bed at rest).
case $SCENE in
  bed) CGDEM_SCENE=(); PEER_SCENE=() ;;
  chute) CGDEM_SCENE=(--set 'gravity=[4.14586, 0, -8.89085]' --set 'groups.0.velocity=[0.5, 0, 0]')
         PEER_SCENE=(-var gx 0.422618 -var gz -0.906308 -var vx 0.5) ;;
  *) echo "compare.sh: --scene must be bed or chute (got $SCENE)" >&2; exit 2 ;;
esac
for n in $SIZES; do
  case $n in 2k|10k|50k|200k) ;; *) echo "compare.sh: --n must be 2k, 10k, 50k, 200k or all (got $n)" >&2; exit 2 ;; esac
done
MPI_FLAGS="${MPIRUN_FLAGS:---oversubscribe}"
[ "$(id -u)" = 0 ] && MPI_FLAGS="$MPI_FLAGS --allow-run-as-root"
export OMP_NUM_THREADS=1   # the peers are MPI-only here; keeps LAMMPS's OpenMP runtime from spreading out
OUT=${OUT:-$HERE/work/compare-$(date +%Y%m%d-%H%M%S)}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
ROWS=$OUT/runs.tsv
# a private copy, so that a rebuild of build/ during the runs neither breaks nor changes them
[ -x "$CGDEM" ] || { echo "compare.sh: no cgdem executable at $CGDEM (set CGDEM)" >&2; exit 2; }
cp "$CGDEM" "$OUT/cgdem"
CGDEM_SRC=$CGDEM
CGDEM=$OUT/cgdem
printf 'n\tcode\tpar\trun\tparticles\tpss\tmaxrss_kb\tcontacts\tke\n' > "$ROWS"

# particle files (git-ignored work/): data files for the peers, the 200k CSV for all
prepare() {
  local n=$1 csv
  mkdir -p "$HERE/work"
  case $n in
    2k) csv=$HERE/work/settled_bed_2k.csv   # the small-N case: the 10k bed's 2000 lowest particles
        [ -s "$csv" ] || $PY "$HERE/beds.py" bottom $SHARED_DATA/settled_bed_10k.csv "$csv" 2000 ;;
    10k) csv=$SHARED_DATA/settled_bed_10k.csv ;;
    50k) csv=$SHARED_DATA/settled_bed_50k.csv ;;
    200k) csv=$HERE/work/settled_bed_200k.csv
          [ -s "$csv" ] || $PY "$HERE/beds.py" tile $SHARED_DATA/settled_bed_50k.csv "$csv" 2 2 ;;
  esac
  [ -s "$HERE/work/bed_$n.data" ] || $PY "$HERE/beds.py" data "$csv" "$HERE/work/bed_$n.data"
  # the floor as a type of its own (in.bed.eepa.liggghts)
  [ -s "$HERE/work/bed_$n.2types.data" ] || $PY "$HERE/beds.py" data "$csv" "$HERE/work/bed_$n.2types.data" 2
}

# sum of the max RSS files of one run (one per rank) in KB
sum_rss() { cat "$@" | awk '/^[0-9]+$/ { s += $1 } END { print s + 0 }'; }

run_cgdem() { # n threads run
  local tag=$OUT/cgdem_$1_t$2_r$3
  # Threads pinned at every count, as in the figures of perf/README.md (by itself cgdem pins only when its
  # threads fill the cores: drivers/kokkos_session.hpp).
  OMP_PROC_BIND=spread /usr/bin/time -f %M -o "$tag.rss" "$CGDEM" run "$HERE/bed_$1.yaml" --threads "$2" --quiet --out "$tag.h5" "${CGDEM_LAW[@]}" "${CGDEM_SCENE[@]}" \
    --set time.end="$($PY -c "print($STEPS * 1e-5)")" >"$tag.out" 2>"$tag.log" || { echo "cgdem failed: $tag.log" >&2; return 1; }
  local pss np contacts_ke
  np=$(sed -n 's/^done: [0-9]* steps of \([0-9]*\) particles.*/\1/p' "$tag.log")
  pss=$(sed -n 's/^done: .*: \([0-9.e+]*\) particle-steps\/s.*/\1/p' "$tag.log")
  contacts_ke=$($PY -c "import h5py; s = h5py.File('$tag.h5', 'r')['series']; print(f\"{int(s['contacts'][-1])}\t{float(s['kinetic_energy'][-1]):.6g}\")")
  rm -f "$tag.h5" "$tag.xdmf"
  printf '%s\tcgdem\t%s\t%s\t%s\t%s\t%s\t%s\n' "$1" "$2" "$3" "$np" "$pss" "$(sum_rss "$tag.rss")" "$contacts_ke" >> "$ROWS"
}

run_peer() { # code n ranks run
  local code=$1 n=$2 np=$3 r=$4 bin input data=$HERE/work/bed_$2.data extra=()
  local tag=$OUT/${code}_${n}_np${np}_r${r}
  if [ "$code" = liggghts ]; then
    bin=$LIGGGHTS
    case $LAW in
      hertz) input=$HERE/in.bed.liggghts ;;
      capillary) input=$HERE/in.bed.capillary.liggghts ;;
      eepa) input=$HERE/in.bed.eepa.liggghts; data=$HERE/work/bed_$n.2types.data ;;
    esac
  else bin=$LMP; input=$HERE/in.bed.lammps; extra=(-var e "$LAMMPS_E" -var law "$LAW" -var gamma "$GAMMA"); fi
  rm -f "$tag.rss".*
  # shellcheck disable=SC2086
  (cd "$OUT" && $MPIRUN $MPI_FLAGS -np "$np" sh -c 'exec /usr/bin/time -f %M -o "$0.${OMPI_COMM_WORLD_RANK:-0}" "$@"' \
      "$tag.rss" "$bin" -in "$input" -var data "$data" -var steps "$STEPS" \
      -var dumpfile "$tag.dump_*.bin" "${extra[@]}" "${PEER_SCENE[@]}" \
      -echo none -log none >"$tag.log" 2>&1) || { echo "$code failed: $tag.log" >&2; return 1; }
  # "Loop time of T on P procs for S steps with N atoms"; the thermo line of the last step: step atoms ke pairs floor
  local row
  row=$(awk -v s="$STEPS" '/^Loop time of/ { t = $4; st = $9; na = $12 }
                           $1 == s && NF == 5 { c = $4 + $5; ke = $3 }
                           END { if (t > 0) printf "%d\t%.6g\t%d\t%.6g", na, na * st / t, c, ke }' "$tag.log")
  [ -n "$row" ] || { echo "$code: no Loop time in $tag.log" >&2; return 1; }
  rm -f "$tag".dump_*.bin
  local atoms pss contacts ke
  IFS=$'\t' read -r atoms pss contacts ke <<<"$row"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$n" "$code" "$np" "$r" "$atoms" "$pss" "$(sum_rss "$tag.rss".*)" "$contacts" "$ke" >> "$ROWS"
}

CGDEM_INFO=$("$CGDEM" info 2>&1 || true)
{
  echo "compare.sh: $(date -u '+%Y-%m-%d %H:%M UTC'), host $(hostname), $(lscpu | sed -n 's/^Model name: *//p'), $CORES cores"
  echo "  load average at start: $(cut -d' ' -f1-3 /proc/loadavg); sizes: $SIZES; scene: $SCENE; law: $LAW$(case $LAW in jkr|dmt) echo " (surface energy $GAMMA J/m^2)" ;; esac); $RUNS runs x $STEPS steps; codes: $CODES"
  # The binary is named by its checksum and build time, since CGDEM may point at a copy built from another
  # commit than the working tree's; the tree's commit is printed as the tree's.
  echo "  cgdem: $CGDEM_SRC (sha256 $(sha256sum "$CGDEM_SRC" | cut -c1-12), built $(date -u -r "$CGDEM_SRC" '+%Y-%m-%d %H:%M UTC')), tree at $(cd "$ROOT" && git log -1 --format='%h %cd' --date=short 2>/dev/null) ($(echo "$CGDEM_INFO" | head -1), $(echo "$CGDEM_INFO" | grep -m1 '^instruction set' || echo 'instruction set: generic'))"
  echo "  LIGGGHTS: $(command -v "$LIGGGHTS") ($(dpkg -S "$(command -v "$LIGGGHTS")" >/dev/null 2>&1 && dpkg-query -W -f 'Debian ${Version}' liggghts || echo 'not from a Debian package')); LAMMPS: $(dpkg-query -W -f '${Version}' lammps 2>/dev/null || echo '?') (restitution input $LAMMPS_E); $($MPIRUN --version 2>&1 | head -1)"
} | tee "$OUT/header.txt"

for n in $SIZES; do
  prepare "$n"
  for r in $(seq 1 "$RUNS"); do
    for code in $CODES; do
      for p in 1 2; do
        if [ "$code" = cgdem ]; then run_cgdem "$n" "$p" "$r"; else run_peer "$code" "$n" "$p" "$r"; fi
        tail -1 "$ROWS" | awk -F'\t' '{ printf "  %-5s %-8s x%s run %s: %.3g particle-steps/s, %.0f MB, %d contacts, KE %.4g J\n", $1, $2, $3, $4, $6, $7 / 1024, $8, $9 }'
      done
    done
  done
done

$PY - "$ROWS" <<'EOF' | tee "$OUT/summary.txt"
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
by = {}
for r in rows:
    by.setdefault((r["n"], r["code"], int(r["par"])), []).append(r)
unit = {"cgdem": "threads", "liggghts": "ranks", "lammps": "ranks"}
med = {}
print()
print(f"{'N':>5} {'code':<9} {'par':>10} {'median p-steps/s':>17} {'min - max':>21} {'B/particle':>11} {'contacts/particle':>18} {'KE at end (J)':>14}")
for key in sorted(by, key=lambda k: (["2k", "10k", "50k", "200k"].index(k[0]), ["cgdem", "liggghts", "lammps"].index(k[1]), k[2])):
    rs = by[key]
    pss = [float(r["pss"]) for r in rs]
    npart = int(rs[0]["particles"])
    rss = statistics.median(float(r["maxrss_kb"]) for r in rs) * 1024 / npart
    cpp = sorted({int(r["contacts"]) / npart for r in rs})
    med[key] = statistics.median(pss)
    c = f"{cpp[0]:.4f}" if len(cpp) == 1 else f"{cpp[0]:.4f}-{cpp[-1]:.4f}"
    kes = sorted({float(r["ke"]) for r in rs})
    ke = f"{kes[0]:.4g}" if len(kes) == 1 else f"{kes[0]:.4g}-{kes[-1]:.4g}"
    print(f"{key[0]:>5} {key[1]:<9} {str(key[2]) + ' ' + unit[key[1]]:>10} {med[key]:>17.4g} "
          f"{min(pss):>10.4g} - {max(pss):<8.4g} {rss:>11.0f} {c:>18} {ke:>14}")
print()
for n in ["2k", "10k", "50k", "200k"]:
    for peer in ["liggghts", "lammps"]:
        parts = []
        for p in (1, 2):
            if (n, "cgdem", p) in med and (n, peer, p) in med:
                parts.append(f"{p} thread/rank {med[(n, 'cgdem', p)] / med[(n, peer, p)]:.3f}")
        if parts:
            print(f"{n:>5} cgdem / {peer:<8}: " + ", ".join(parts))
    for code in ["cgdem", "liggghts", "lammps"]:
        if (n, code, 1) in med and (n, code, 2) in med:
            # Also run by run (each 2-thread/rank run over the 1-thread/rank run just before it): on a
            # shared machine the spread of these shows how much of the median ratio is the machine.
            one = {r["run"]: float(r["pss"]) for r in by[(n, code, 1)]}
            pairs = sorted(float(r["pss"]) / one[r["run"]] for r in by[(n, code, 2)] if r["run"] in one)
            print(f"{n:>5} 2-vs-1 speed-up {code:<8}: {med[(n, code, 2)] / med[(n, code, 1)]:.3f} "
                  f"(run by run {' '.join(f'{x:.2f}' for x in pairs)})")
EOF
echo "rows: $ROWS"
