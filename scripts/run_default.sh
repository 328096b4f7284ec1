#!/usr/bin/env bash
# README command 1: set up, build, and run the default scene (a pile formed by lifting a cylinder),
# leaving results.h5, results.xdmf (open in ParaView) and results.png in the current directory.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bash "$repo/scripts/build.sh"
"$repo/build/cgdem" run "$repo/scenes/pile_in_cylinder.yaml" --out results.h5 "$@"
/usr/bin/python3 "$repo/scripts/plot_results.py" results.h5 results.png
