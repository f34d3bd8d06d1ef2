#!/usr/bin/env bash
# A good citizen under load: `scanmesh denoise` with the default thread count while every core is kept
# busy by another process, against one thread under the same load, and against the OpenMP default
# (threads that spin while they wait, OMP_WAIT_POLICY=active) for comparison. Input: bun4's mesh is too
# small to matter, so the 202k-face dragon of ../shared/data, 20 iterations. Skips when it is absent.
# usage: bench/under_load.sh [DATA_DIR]   (from the repository root, after scripts/build.sh)
set -euo pipefail
data=${1:-../shared/data}
mesh="$data/meshes/dragon-202k.ply"
if [ ! -f "$mesh" ]; then echo "skipped: $mesh not found"; exit 0; fi
tmp=$(mktemp -d)
busy=()
cleanup() { for p in "${busy[@]}"; do kill "$p" 2> /dev/null || true; done; rm -rf "$tmp"; }
trap cleanup EXIT
run() {  # prints the wall time of one run
  local start end
  start=$(date +%s.%N)
  "$@" > /dev/null 2>&1
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }'
}
den=(build/bin/scanmesh denoise "$mesh" "$tmp/out.ply" --iterations 20)
echo "| load | default threads | --threads 1 | OMP_WAIT_POLICY=active, default threads |"
echo "|---|---|---|---|"
for load in idle busy; do
  if [ "$load" = busy ]; then
    for _ in $(seq "$(nproc)"); do (while :; do :; done) & busy+=($!); done
  fi
  d=() o=() a=()
  for _ in 1 2 3; do
    d+=("$(run "${den[@]}")")
    o+=("$(run "${den[@]}" --threads 1)")
    a+=("$(run env OMP_WAIT_POLICY=active "${den[@]}")")
  done
  echo "| $load ($(nproc) cores) | ${d[*]} s | ${o[*]} s | ${a[*]} s |"
done
