#!/bin/bash
# Restitution match of the peer comparison (perf/peers/README.md).
#
#   impact.sh [--dt DT] [--e E]
#
# Measures the ACHIEVED restitution of cgdem, LIGGGHTS and LAMMPS for the bed material (E 5 MPa, nu 0.3,
# 1 mm spheres, rho 2500) in a head-on impact of two spheres (0.5 m/s relative) and a sphere-wall impact
# (0.5 m/s), at the benchmark time step (default 1e-5 s) with input restitution E (default 0.9).
# cgdem and LIGGGHTS use the same beta(e) = ln e / sqrt(ln^2 e + pi^2) damping; LAMMPS 'damping tsuji' maps e
# through Tsuji's polynomial instead, so the script bisects the LAMMPS input e that reproduces cgdem's
# achieved pair restitution, checks it on the wall impact too, and prints LAMMPS_E=<value> last.
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/../../../.." && pwd)
CGDEM=${CGDEM:-$ROOT/build/cgdem}
LIGGGHTS=${LIGGGHTS:-liggghts}
LMP=${LMP:-lmp}
PY=/usr/bin/python3
DT=1e-5
E_IN=0.9
while [ $# -gt 0 ]; do
  case $1 in
    --dt) DT=$2; shift 2 ;;
    --e) E_IN=$2; shift 2 ;;
    -h|--help) sed -n 2,12p "$0"; exit 0 ;;
    *) echo "impact.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
STEPS=$($PY -c "print(round(1e-3/$DT))")   # 1 ms: approach 0.1 mm at 0.5 m/s, contact ~0.15 ms, rebound
W=$HERE/../work/impact
mkdir -p "$W"
cd "$W"
$PY "$HERE/../beds.py" pair pair.data 0.5
$PY "$HERE/../beds.py" wall wall.data 0.5

# achieved e from the final velocities: pair (v2x - v1x) / 0.5, wall v1z / 0.5
cgdem_e() { # scene geometry(pair|wall)
  "$CGDEM" run "$HERE/$1" --threads 1 --quiet --out "cg_$2.h5" --set time.step="$DT" --set time.end=1e-3 \
    --set materials.beads.restitution="$E_IN" >/dev/null 2>"cg_$2.log"
  $PY - "cg_$2.h5" "$2" <<'EOF'
import sys, h5py
f = h5py.File(sys.argv[1], "r")
last = sorted(f["frames"].keys())[-1]
v = f["frames"][last]["velocity"][:]
ids = list(f["frames"][last]["id"][:])
if sys.argv[2] == "pair":
    print("%.6f" % ((v[ids.index(2), 0] - v[ids.index(1), 0]) / 0.5))
else:
    print("%.6f" % (v[0, 2] / 0.5))
EOF
}
peer_e() { # binary input geometry(pair|wall) e
  local wall=0; [ "$3" = wall ] && wall=1
  "$1" -in "$HERE/$2" -var data "$3.data" -var wall $wall -var e "$4" -var dt "$DT" -var steps "$STEPS" \
    -echo none -log none 2>&1 | awk -v g="$3" '/^IMPACT/ { if (g == "pair") printf "%.6f\n", ($4 - $2) / 0.5;
                                                           else printf "%.6f\n", $3 / 0.5 }'
}

CG_PAIR=$(cgdem_e impact.yaml pair)
CG_WALL=$(cgdem_e wall.yaml wall)
LG_PAIR=$(peer_e "$LIGGGHTS" in.impact.liggghts pair "$E_IN")
LG_WALL=$(peer_e "$LIGGGHTS" in.impact.liggghts wall "$E_IN")
LM_PAIR=$(peer_e "$LMP" in.impact.lammps pair "$E_IN")
LM_WALL=$(peer_e "$LMP" in.impact.lammps wall "$E_IN")

# bisection of the LAMMPS input e on the pair impact (achieved e increases with the input e)
lo=0.5; hi=0.999
for _ in $(seq 1 30); do
  mid=$($PY -c "print('%.8f' % (($lo + $hi) / 2))")
  got=$(peer_e "$LMP" in.impact.lammps pair "$mid")
  if $PY -c "import sys; sys.exit(0 if $got < $CG_PAIR else 1)"; then lo=$mid; else hi=$mid; fi
  if $PY -c "import sys; sys.exit(0 if $hi - $lo < 1e-6 else 1)"; then break; fi
done
LAMMPS_E=$($PY -c "print('%.5f' % (($lo + $hi) / 2))")
LM_PAIR_M=$(peer_e "$LMP" in.impact.lammps pair "$LAMMPS_E")
LM_WALL_M=$(peer_e "$LMP" in.impact.lammps wall "$LAMMPS_E")

printf 'restitution check: dt %s s, %s steps, impact speed 0.5 m/s, input e %s\n' "$DT" "$STEPS" "$E_IN"
printf '%-34s %10s %10s\n' "code (input e)" "pair e" "wall e"
printf '%-34s %10s %10s\n' "cgdem ($E_IN)" "$CG_PAIR" "$CG_WALL"
printf '%-34s %10s %10s\n' "LIGGGHTS ($E_IN)" "$LG_PAIR" "$LG_WALL"
printf '%-34s %10s %10s\n' "LAMMPS tsuji ($E_IN)" "$LM_PAIR" "$LM_WALL"
printf '%-34s %10s %10s\n' "LAMMPS tsuji ($LAMMPS_E, bisected)" "$LM_PAIR_M" "$LM_WALL_M"
echo "LAMMPS_E=$LAMMPS_E"
