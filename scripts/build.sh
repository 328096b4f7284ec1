#!/usr/bin/env bash
# Set up (scripts/setup.sh, skipped when done) and build cgdem in Release into build/.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bash "$repo/scripts/setup.sh"
cmake -S "$repo" -B "$repo/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCGDEM_EXCLUDE= >/dev/null
cmake --build "$repo/build" --parallel "$(nproc)"
