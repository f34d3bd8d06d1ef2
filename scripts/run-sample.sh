#!/usr/bin/env bash
# The main job on a bundled real scan (installs dependencies and builds first if needed):
# configs/scan_to_mesh.yaml turns data/bun0.pcd (a Stanford bunny range scan) into a clean, denoised mesh
# with a quality report; then the bundled noisy Fandisk is denoised and measured against its ground truth.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh > build.log 2>&1 || { echo "build failed; see build.log" >&2; tail -20 build.log >&2; exit 1; }
mkdir -p out
build/bin/scanmesh run configs/scan_to_mesh.yaml --input data/bun0.pcd --output out/bun0.ply
echo
build/bin/scanmesh run configs/reproduce_paper.yaml --output out/fandisk-paper.ply
echo
echo "mesh from the scan:   out/bun0.ply"
echo "its report:           out/bun0.report.html (open in a browser), out/bun0.report.json, out/bun0.report/*.png"
echo "paper experiment:     out/fandisk-paper.ply, report out/fandisk-paper.report.html"
