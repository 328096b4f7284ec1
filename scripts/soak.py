#!/usr/bin/env python3
"""Soak test: runs a flowing scene for a million steps and samples cgdem's resident memory (VmRSS) once a
second; writes the samples as CSV and plots the memory curve (docs/reliability.md shows it).

    /usr/bin/python3 scripts/soak.py [--cgdem build/cgdem] [--steps 1000000] [--csv soak.csv] [--png soak.png]

The scene is scenes/rotating_drum.yaml (400 beads tumbling in a drum at 30 rpm, auto step ~2.7e-5 s) run to
steps x step, with a frame every second of simulated time and a checkpoint every 5 s, so that the writer,
the checkpoints and the neighbour list rebuilds all run throughout.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile
import time

repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ap = argparse.ArgumentParser()
ap.add_argument("--cgdem", default=os.path.join(repo, "build", "cgdem"))
ap.add_argument("--scene", default=os.path.join(repo, "scenes", "rotating_drum.yaml"))
ap.add_argument("--steps", type=int, default=1000000)
ap.add_argument("--csv", default="soak.csv")
ap.add_argument("--png", default="soak.png")
a = ap.parse_args()

check = subprocess.run([a.cgdem, "check", a.scene], capture_output=True, text=True, check=True).stdout
dt = float(re.search(r"time step\s+(\S+) s", check).group(1))
end = a.steps * dt * 1.001  # `check` prints 4 digits of the step: a little more so that no step is missing
work = tempfile.mkdtemp(prefix="cgdem_soak_")
cmd = [a.cgdem, "run", a.scene, "--threads", "1", "--set", f"time.end={end!r}", "--set", "output.every=1.0",
       "--checkpoint-every", "5.0", "--out", os.path.join(work, "soak.h5")]
log = open(os.path.join(work, "soak.log"), "w")
start = time.time()
p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
samples = []  # (wall s, VmRSS KiB)
while p.poll() is None:
    try:
        with open(f"/proc/{p.pid}/status") as f:
            rss = int(re.search(r"VmRSS:\s+(\d+)", f.read()).group(1))
        samples.append((time.time() - start, rss))
    except (OSError, AttributeError):
        pass
    time.sleep(1.0)
log.close()
text = open(os.path.join(work, "soak.log")).read()
steps = re.search(r"done.*?: (\d+) steps", text)
print(f"exit {p.returncode}, {steps.group(1) if steps else '?'} steps of dt {dt:.4g} s in {time.time() - start:.0f} s; "
      f"RSS first {samples[0][1] / 1024:.1f} MiB, after 10 % {samples[len(samples) // 10][1] / 1024:.1f} MiB, "
      f"last {samples[-1][1] / 1024:.1f} MiB, max {max(s[1] for s in samples) / 1024:.1f} MiB ({len(samples)} samples); "
      f"output in {work}")
with open(a.csv, "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["wall_s", "rss_kib"])
    w.writerows(samples)

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
fig, ax = plt.subplots(figsize=(7, 3.5))
ax.plot([s[0] for s in samples], [s[1] / 1024 for s in samples], lw=1.2)
ax.set_xlabel("wall time (s)")
ax.set_ylabel("resident memory (MiB)")
ax.set_ylim(0, max(s[1] for s in samples) / 1024 * 1.15)
ax.set_title(f"cgdem soak: {os.path.basename(a.scene)}, {a.steps:,} steps, 400 particles, 1 thread")
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(a.png, dpi=120)
sys.exit(p.returncode)
