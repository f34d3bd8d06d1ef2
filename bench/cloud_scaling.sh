#!/usr/bin/env bash
# Scaling of the main job on point clouds, whole command line with I/O: virtual scans of the 202k-face
# dragon of ../shared/data (`scanmesh scan`, depth noise 0.3 mean edges) at growing resolution, each run
# through configs/scan_to_mesh.yaml. Prints a Markdown table: points, seconds per stage (from the job's
# own stage lines), total seconds, peak resident memory (GNU time), the meshing method mesh.auto chose,
# faces, the run's status, and E_v of the final mesh against the clean dragon (relative to its bounding-box
# diagonal, `scanmesh eval OUT --reference dragon-202k.ply`). Skips when ../shared/data is absent.
#   level 1: 6 views of 640 x 480 (~0.2M points)      level 2: 6 views of 1280 x 960 (~0.9M)
#   level 3: 12 views of 1600 x 1200 (~2.7M)          level 4: 12 views of 2880 x 2160 (~9M)
# usage: bench/cloud_scaling.sh [DATA_DIR]   (from the repository root, after scripts/build.sh;
#        LEVELS=N runs levels 1..N, default 2; FROM=K starts at level K)
set -euo pipefail
data=${1:-../shared/data}
levels=${LEVELS:-2}
from=${FROM:-1}
bin=build/bin
if [ ! -f "$data/meshes/dragon-202k.ply" ]; then echo "skipped: $data/meshes/dragon-202k.ply not found"; exit 0; fi
if [ ! -x /usr/bin/time ]; then echo "skipped: GNU time (/usr/bin/time, package 'time') not installed"; exit 0; fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
views=(0 6 6 12 12)
widths=(0 640 1280 1600 2880)
heights=(0 480 960 1200 2160)
stages="cloud.dequantize cloud.voxel cloud.outliers cloud.normals mesh.auto mesh.cleanup mesh.denoise"
printf "| points | scan (s) |"
for s in $stages; do printf " %s (s) |" "$s"; done
printf " main job (s) | peak MB | method | faces | status | E_v |\n|---|---|"
for s in $stages; do printf "%s" "---|"; done
printf "%s\n" "---|---|---|---|---|---|"
for k in $(seq "$from" "$levels"); do
  cloud="$tmp/scan-L$k.ply"
  /usr/bin/time -f "%e" -o "$tmp/scan.time" "$bin/scanmesh" scan "$data/meshes/dragon-202k.ply" "$cloud" -q \
    --views "${views[$k]}" --width "${widths[$k]}" --height "${heights[$k]}"
  /usr/bin/time -f "%e %M" -o "$tmp/job.time" "$bin/scanmesh" run configs/scan_to_mesh.yaml --input "$cloud" \
    --output "$tmp/out-L$k.ply" > "$tmp/job.log" 2>&1 || true
  read -r secs mem < "$tmp/job.time"
  points=$(awk '/^read / {print $4; exit}' "$tmp/job.log")
  printf "| %s | %s |" "${points:-?}" "$(cat "$tmp/scan.time")"
  for s in $stages; do printf " %s |" "$(awk -v s="$s" '$1 == s && $3 == "s" {print $2; exit}' "$tmp/job.log")"; done
  method=$(awk '$1 == "mesh.auto" && $3 == "s" {print ($0 ~ /: Poisson$/ ? "Poisson" : ($0 ~ /organized meshing/ ? "organized" : "greedy projection")); exit}' "$tmp/job.log")
  faces=$(awk '$1 == "mesh.denoise" && $3 == "s" {print $6; exit}' "$tmp/job.log")
  status=$(grep -q '^degraded' "$tmp/job.log" && echo degraded || echo ok)
  ev=$("$bin/scanmesh" eval "$tmp/out-L$k.ply" --reference "$data/meshes/dragon-202k.ply" 2>/dev/null | awk '$1 == "E_v:" {gsub(/[(]/, "", $3); print $3; exit}')
  printf " %s | %s | %s | %s | %s | %s |\n" "$secs" "$(awk -v m="$mem" 'BEGIN {printf "%.0f", m / 1024}')" "$method" "$faces" "$status" "${ev:-?}"
done
