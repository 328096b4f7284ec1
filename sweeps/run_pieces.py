"""The HDF5 files of one run of a sweep, in time order, and a run's record (shared by the sweep scripts).

A run continued from checkpoints over several sittings leaves run.part1.h5, run.part2.h5, ... beside the
last piece's run.h5 (docs/sweeps.md, "Runs longer than a sitting"); a two-stage run (cgdem sweep
--first-stage) begins with first_stage.h5. A piece starts at its checkpoint, so consecutive pieces may
hold the same frame time: readers keep one.
"""
import os
import re


def run_pieces(rundir, with_first_stage=False):
    """The existing files of the run in `rundir`, oldest first: first_stage.h5 (when asked for), the
    run.part<N>.h5 in the order of N, then run.h5."""
    names = os.listdir(rundir) if os.path.isdir(rundir) else []
    parts = sorted((n for n in names if re.fullmatch(r"run\.part\d+\.h5", n)), key=lambda n: int(n[8:-3]))
    files = (["first_stage.h5"] if with_first_stage else []) + parts + ["run.h5"]
    return [os.path.join(rundir, n) for n in files if os.path.exists(os.path.join(rundir, n))]


def read_record(path):
    """The "key value" lines of a sweep record (drivers/sweep_command.cpp, write_record) as a dict of
    strings; an analysis value is the key "value" followed by its name: see record_value."""
    rec = {}
    with open(path) as f:
        for line in f:
            parts = line.rstrip("\n").split(" ", 1)
            if len(parts) == 2:
                rec[parts[0]] = parts[1]
    return rec


def record_value(path, name):
    """The analysis value `name` of a sweep record (its line "value <name> <number>")."""
    with open(path) as f:
        for line in f:
            parts = line.split()
            if len(parts) == 3 and parts[0] == "value" and parts[1] == name:
                return float(parts[2])
    raise KeyError(f"{path}: no value {name}")
