#!/usr/bin/env bash
# Builds the libFuzzer harnesses (build preset `fuzz`: the fuzzers of the clang ASan + UBSan build in
# build-asan, which scripts/sanitize.sh shares) and runs each for a while.
#   bash scripts/fuzz.sh [SECONDS_PER_HARNESS] [HARNESS ...]   (default: 20 s each, all harnesses)
# Seeds come from tests/fuzz/corpus/<format> and tests/hostile; what a run discovers is kept in
# build-asan/fuzz/corpus/<harness> for the next run. A finding (crash, leak of an exception, timeout, out of
# memory) stops with a non-zero exit code and leaves the reproducer in build-asan/fuzz/findings/.
# A longer local campaign: bash scripts/fuzz.sh 600  (ten minutes per harness).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
shift || true
bash scripts/install-deps.sh
cmake --preset asan-ubsan > build-fuzz.log 2>&1 || { tail -30 build-fuzz.log >&2; exit 1; }
cmake --build --preset fuzz -j"$(nproc)" >> build-fuzz.log 2>&1 || { tail -30 build-fuzz.log >&2; exit 1; }
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(obj off ply stl pcd xyz range conf pipeline fill)
mkdir -p build-asan/fuzz/findings
for h in "${harnesses[@]}"; do
  seeds=tests/fuzz/corpus/$h
  case $h in
    range) seeds=tests/fuzz/corpus/range ;;
    pipeline) seeds=tests/fuzz/corpus/yaml ;;
    fill) seeds=tests/fuzz/corpus/fill ;;
  esac
  work=build-asan/fuzz/corpus/$h
  mkdir -p "$work"
  extra=()
  for f in tests/hostile/*; do
    case "$h:$f" in
      obj:*.obj|off:*.off|fill:*.off|ply:*.ply|stl:*.stl|pcd:*.pcd|xyz:*.xyz|range:*.ply) extra+=("$f") ;;
    esac
  done
  [ ${#extra[@]} -gt 0 ] && cp "${extra[@]}" "$work"/
  log=build-asan/fuzz/fuzz_$h.log
  if ! build-asan/bin/fuzz_"$h" "$work" "$seeds" -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
      -artifact_prefix=build-asan/fuzz/findings/"$h"- -print_final_stats=1 > "$log" 2>&1; then
    grep -E "ERROR|SUMMARY|==[0-9]+==" "$log" | head -20 >&2 || true
    echo "fuzz_$h found a problem; reproducer in build-asan/fuzz/findings/, log $log" >&2
    exit 1
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  echo "fuzz_$h: ${seconds} s, ${runs:-?} inputs, no finding (corpus $(ls "$work" | wc -l) files)"
done
