#!/usr/bin/env bash
# README command 2: set up, build, and run every test (ctest; GoogleTest inside).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
bash "$repo/scripts/build.sh"
cd "$repo/build"
# One test process at a time: tests time nothing, but the OpenMP ones expect the cores to themselves.
ctest --output-on-failure --timeout 900
