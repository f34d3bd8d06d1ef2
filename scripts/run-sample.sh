#!/usr/bin/env bash
# The main job on bundled samples (installs dependencies and builds first if needed):
#  1. a raw scan (data/bun0.pcd, a Stanford bunny range scan) -> triangle mesh -> denoised mesh;
#  2. the noisy Fandisk (data/fandisk-noisy.obj) denoised with --auto and measured against its ground truth.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh > build.log 2>&1 || { echo "build failed; see build.log" >&2; tail -20 build.log >&2; exit 1; }
mkdir -p out
build/bin/scanmesh mesh data/bun0.pcd out/bun0-mesh.ply
build/bin/scanmesh denoise out/bun0-mesh.ply out/bun0-denoised.ply --auto
build/bin/scanmesh eval out/bun0-denoised.ply --json out/bun0-denoised.metrics.json
echo
build/bin/scanmesh denoise data/fandisk-noisy.obj out/fandisk-denoised.ply --auto
build/bin/scanmesh eval out/fandisk-denoised.ply --reference data/fandisk-clean.obj --json out/fandisk-denoised.metrics.json
echo
echo "scan -> mesh: out/bun0-mesh.ply, denoised: out/bun0-denoised.ply (metrics out/bun0-denoised.metrics.json)"
echo "fandisk denoised: out/fandisk-denoised.ply (metrics against ground truth: out/fandisk-denoised.metrics.json)"
