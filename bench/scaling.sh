#!/usr/bin/env bash
# Scaling of the denoiser, whole command line with I/O: the 202k-face dragon of ../shared/data split
# 1 -> 4 (bench/big_meshes.cpp) to 810k and 3.2M faces (LEVELS=3: 13M, ~5 GB), Gaussian noise 0.3,
# `scanmesh denoise` with the defaults for 20 and 100 iterations. Prints a Markdown table: seconds,
# seconds per iteration (from the difference of the two runs), seconds per million faces per iteration,
# peak resident memory (GNU time) and bytes per face. Skips when ../shared/data is absent.
# usage: bench/scaling.sh [DATA_DIR]   (from the repository root, after scripts/build.sh)
set -euo pipefail
data=${1:-../shared/data}
levels=${LEVELS:-2}
bin=build/bin
if [ ! -f "$data/meshes/dragon-202k.ply" ]; then echo "skipped: $data/meshes/dragon-202k.ply not found"; exit 0; fi
if [ ! -x /usr/bin/time ]; then echo "skipped: GNU time (/usr/bin/time, package 'time') not installed"; exit 0; fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin/scanmesh_big_meshes" "$data" "$tmp" --levels "$levels" > /dev/null
echo "| faces | 20 its (s) | 100 its (s) | s / iteration | s / (M faces x iteration) | peak MB | bytes / face |"
echo "|---|---|---|---|---|---|---|"
for k in $(seq 0 "$levels"); do
  in="$tmp/dragon-L$k.ply"
  faces=$((202520 * 4 ** k))
  declare -A secs mem
  for its in 20 100; do
    /usr/bin/time -f "%e %M" -o "$tmp/time" "$bin/scanmesh" denoise "$in" "$tmp/out.ply" --iterations "$its" -q
    read -r secs[$its] mem[$its] < "$tmp/time"
  done
  awk -v f="$faces" -v a="${secs[20]}" -v b="${secs[100]}" -v m="${mem[100]}" 'BEGIN {
    it = (b - a) / 80; printf "| %d | %.2f | %.2f | %.4f | %.4f | %.0f | %.0f |\n", f, a, b, it, it / (f / 1e6), m / 1024, m * 1024 / f }'
done
