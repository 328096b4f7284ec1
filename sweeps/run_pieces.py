"""The HDF5 files of one run of a sweep, in time order, and a run's record (shared by the sweep scripts).

A run continued from checkpoints over several sittings leaves run.part1.h5, run.part2.h5, ... beside the
last piece's run.h5 (docs/sweeps.md, "Runs longer than a sitting"); a two-stage run (cgdem sweep
--first-stage) begins with first_stage.h5. A piece starts at its checkpoint, so consecutive pieces may
hold the same frame time: readers keep one.
"""
import math
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


def combined_scatter(sd, ref_sd, ref_mean):
    """The seed-to-seed scatter an error is judged against: sqrt(sd^2 + ref_sd^2) / ref_mean, the two sets'
    standard deviations combined (a set of one seed, sd NaN, adds nothing). "Within" means |error| <= it."""
    nan_to_zero = lambda v: 0.0 if v != v else v
    return math.hypot(nan_to_zero(sd), nan_to_zero(ref_sd)) / ref_mean


def cgdem_binary():
    """The cgdem executable the scripts call: $CGDEM, else the repository's build/cgdem, else `cgdem` on
    the PATH."""
    repo_build = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "build", "cgdem")
    return os.environ.get("CGDEM") or (repo_build if os.access(repo_build, os.X_OK) else "cgdem")


def stored_scene(path):
    """The scene a result file was run with (its `scene` attribute, the resolved YAML), as a dict."""
    import h5py
    import yaml

    with h5py.File(path, "r") as f:
        return yaml.safe_load(f.attrs["scene"])


def analysis_of(scene, kind):
    """(index, spec) of the scene's first analysis of type `kind`."""
    return next((k, a) for k, a in enumerate(scene.get("analyses", [])) if a.get("type") == kind)


def analyse(files, sets, per_frame=True):
    """`cgdem analyse FILES --set ...` (sets: "key.path=value" strings): every frame's outputs as a numpy
    record array (per_frame), or the last frame's as a dict of floats. Exits with cgdem's message when it
    fails."""
    import subprocess
    import sys
    import tempfile

    import numpy as np

    with tempfile.TemporaryDirectory() as tmp:
        table = os.path.join(tmp, "frames.csv")
        cmd = [cgdem_binary(), "analyse", *files] + [x for s in sets for x in ("--set", s)]
        if per_frame:
            cmd += ["--csv", table]
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f"{' '.join(cmd)} failed: {done.stderr.strip()}")
        if per_frame:
            return np.genfromtxt(table, delimiter=",", names=True)
    return {name: float(value) for name, value in (line.split(" ", 1) for line in done.stdout.splitlines() if " " in line)}
