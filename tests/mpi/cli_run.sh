#!/usr/bin/env bash
# `mpirun -np N cgdem run` end to end (ctest Mpi.cli): the 10k bed for 400 steps in one process, on 2
# ranks, and on 2 ranks to step 200 then restarted from the checkpoint on 4 ranks; the result files are
# the single-process form (rows in id order) and their last frames agree to round-off.
#   cli_run.sh CGDEM_BINARY SHARED_DIR WORK_DIR
set -euo pipefail
cgdem=$1 shared=$2 work=$3
repo=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$work"
cd "$work"
cat > bed.yaml <<EOF
domain: {lo: [0, 0, 0], hi: [0.02031, 0.02031, 0.04], periodic: [true, true, false]}
gravity: [0, 0, -9.81]
materials:
  beads: {density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.3, restitution: 0.9, friction: 0.3}
contact: {normal: hertz, tangential: mindlin}
groups:
  - {name: bed, material: beads, placement: {type: file, file: $shared/data/settled_bed_10k.csv}}
walls:
  - {name: floor, type: plane, material: beads, point: [0, 0, 0], normal: [0, 0, 1], motion: {velocity: [0, 0, 0.05]}}
time: {end: 0.004, step: 1.0e-5}
output: {every: 0.002, file: bed.h5}
stability: {overlap_tolerance: 0.05}
EOF
mpi=(mpirun --oversubscribe --bind-to none)
"$cgdem" run bed.yaml --out one.h5 --threads 1 --quiet
"${mpi[@]}" -np 2 "$cgdem" run bed.yaml --out two.h5 --threads 1 --quiet 2> two.log
grep -q 'MPI communication' two.log || { echo "no MPI line in the 2-rank summary:"; cat two.log; exit 1; }
# Stopped at step 200 by time.end, checkpoint there; then the whole run restarted on 4 ranks.
"${mpi[@]}" -np 2 "$cgdem" run bed.yaml --set time.end=0.002 --out half.h5 --checkpoint-every 0.002 --threads 1 --quiet
"${mpi[@]}" -np 4 "$cgdem" run bed.yaml --restart half.checkpoint.h5 --out restarted.h5 --threads 1 --quiet
# A sweep shares its runs among the ranks; rank 0 writes the table of all of them.
rm -rf sweep
"${mpi[@]}" -np 2 "$cgdem" sweep "$repo/sweeps/tiny_pile.yaml" --laws bond --k 1,2 --set time.end=0.05 \
  --out sweep --no-plots --quiet
for run in reference bond_k2; do
  [ -s "sweep/records/$run.txt" ] || { echo "sweep under 2 ranks: no record of $run"; exit 1; }
done
[ "$(grep -c '' sweep/sweep.csv)" -ge 3 ] || { echo "sweep.csv lacks a row"; cat sweep/sweep.csv; exit 1; }
# Another command under several ranks: one line, exit 2.
set +e
"${mpi[@]}" -np 2 "$cgdem" check bed.yaml > check.log 2>&1
code=$?
set -e
[ "$code" = 2 ] || { echo "cgdem check under 2 ranks exited $code, expected 2"; cat check.log; exit 1; }
/usr/bin/python3 - <<'EOF'
import h5py, numpy as np
def last(name):
    f = h5py.File(name)
    k = sorted(f["frames"].keys())[-1]
    return {x: f["frames"][k][x][:] for x in ["id", "position", "velocity", "angular_velocity"]}, f["frames"][k].attrs.get("step")
ref, step = last("one.h5")
for name in ["two.h5", "restarted.h5"]:
    got, s = last(name)
    assert (got["id"] == ref["id"]).all(), name + ": ids differ"
    dx = np.abs(got["position"] - ref["position"]).max()
    dv = np.abs(got["velocity"] - ref["velocity"]).max()
    print(f"{name}: step {s} against {step}: max |dx| {dx:.3g} m, |dv| {dv:.3g} m/s")
    assert dx < 2e-13 and dv < 1e-11, name + " is not the one-process trajectory"
EOF
