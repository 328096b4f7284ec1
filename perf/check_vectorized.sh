#!/usr/bin/env bash
# Whether the force pass's loop over a batch of pairs (kernels/contact_forces.hpp, the `for (int l = 0; l <
# kLanes; ++l)` loop of `evaluate`) vectorizes for every compiled contact law. A law whose loop does not
# vectorize runs its pairs one at a time, several times slower (perf/README.md, "Cohesive laws").
# Recompiles each drivers/physics_*.cpp with the build's own flags (from build/compile_commands.json) plus
# GCC's vectorizer report, and prints per file how many instances of the loop (one per law and backend)
# vectorized. Exit 1 if any did not.
#   perf/check_vectorized.sh [BUILD_DIR]        (default build/; configured as README says)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$repo/build}
[ -f "$build/compile_commands.json" ] || { echo "check_vectorized.sh: no $build/compile_commands.json" >&2; exit 2; }
line=$(grep -n 'for (int l = 0; l < kLanes; ++l) {' "$repo/kernels/contact_forces.hpp" | head -1 | cut -d: -f1)
[ -n "$line" ] || { echo "check_vectorized.sh: the lane loop is not in kernels/contact_forces.hpp" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
/usr/bin/python3 - "$build/compile_commands.json" > "$tmp/commands" <<'EOF'
import json, shlex, sys
for e in json.load(open(sys.argv[1])):
    if "/drivers/physics_" in e["file"] and e["file"].endswith(".cpp") and "registry" not in e["file"]:
        args = shlex.split(e["command"])
        out = args.index("-o")
        args[out + 1] = "/dev/null"
        print(e["directory"] + "\t" + e["file"] + "\t" + shlex.join(args))
EOF
while IFS=$'\t' read -r dir file cmd; do
  report=$tmp/$(basename "$file").txt
  (cd "$dir" && eval "$cmd -fopt-info-vec-all=$report")
  done_=$(grep -c "contact_forces.hpp:$line:[0-9]*: optimized: loop vectorized" "$report" || true)
  missed=$(grep -c "contact_forces.hpp:$line:[0-9]*: missed: couldn't vectorize loop" "$report" || true)
  printf '%-40s lane loop vectorized in %d instance(s), not vectorized in %d\n' "$(basename "$file")" "$done_" "$missed"
  [ "$missed" -eq 0 ] || status=1
done < "$tmp/commands"
exit $status
