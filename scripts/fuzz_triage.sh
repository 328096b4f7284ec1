#!/usr/bin/env bash
# Sorts the findings of one fuzz target (build-fuzz/findings/<target>/) by where they happen: reruns the
# target on each saved input and names the first stack frame in cgdem's sources (core/, drivers/, models/,
# kernels/) or, if none comes before it, in libhdf5 / yaml-cpp. A finding whose first frame is cgdem's is a
# bug to fix and to turn into a test; one inside a library is contained by cgdem (docs/reliability.md).
# A hang takes the 5 s time limit to show its stack: only the first TIMEOUTS (default 20) timeout-* files are
# rerun, the count of the others is printed.
#   bash scripts/fuzz_triage.sh checkpoint
#   TIMEOUTS=1000 bash scripts/fuzz_triage.sh checkpoint
set -uo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
t=${1:?target: scene, particles or checkpoint}
bin="$repo/build-fuzz/fuzz_$t"
dir="$repo/build-fuzz/findings/$t"
[ -x "$bin" ] || { echo "no $bin: run scripts/fuzz.sh $t first" >&2; exit 2; }
timeouts=(); for f in "$dir"/timeout-*; do [ -f "$f" ] && timeouts+=("$f"); done
limit=${TIMEOUTS:-20}
[ ${#timeouts[@]} -le "$limit" ] || echo "(rerunning $limit of ${#timeouts[@]} timeouts)"
for f in "$dir"/crash-* "$dir"/oom-* "${timeouts[@]:0:$limit}"; do
  [ -f "$f" ] || continue
  log=$(cd "$dir" && ASAN_OPTIONS=detect_leaks=0 timeout 60 "$bin" -timeout=5 -rss_limit_mb=2048 "$f" 2>&1)
  kind=$(grep -oE 'SUMMARY: [A-Za-z]+: [A-Za-z-]+|ERROR: libFuzzer: [a-z-]+|runtime error' <<<"$log" | head -n 1 |
         sed -e 's/SUMMARY: //' -e 's/ERROR: //')
  [ -n "$kind" ] || kind="no longer reproduces"
  where=$(grep -E '^ +#[0-9]+ ' <<<"$log" | grep -vE 'fuzzer::|__sanitizer|__asan|__interceptor|sysdeps|libc\.so|libstdc\+\+|/c\+\+/|LLVMFuzzerTestOneInput|_start|\(/[^ ]*fuzz_'"$t"'\+' |
          head -n 1 | sed -E -e 's/^ +#[0-9]+ 0x[0-9a-f]+ (in )?//' -e 's/\(BuildId.*//' -e 's/\(\/[^ ]*\/(lib[a-z0-9_.-]+)\+0x[0-9a-f]+\)/[\1]/' -e 's|'"$repo"'/||' |
          cut -c1-110)
  case "$where" in
    *core/* | *setup/* | *drivers/* | *models/* | *kernels/*) owner=cgdem ;;
    *libhdf5* | H5*) owner=libhdf5 ;;
    *yaml*) owner=yaml-cpp ;;
    *) owner=other ;;
  esac
  printf '%s\t%s\t%s\n' "$owner" "$kind" "$where"
done | sort | uniq -c | sort -rn
