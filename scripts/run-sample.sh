#!/usr/bin/env bash
# The main job on the bundled sample: denoise a noisy scan-like mesh with --auto and measure the result
# against its ground truth. Installs dependencies and builds first if needed.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh > build.log 2>&1 || { echo "build failed; see build.log" >&2; tail -20 build.log >&2; exit 1; }
mkdir -p out
build/bin/scanmesh denoise data/fandisk-noisy.obj out/fandisk-denoised.ply --auto
build/bin/scanmesh eval out/fandisk-denoised.ply --reference data/fandisk-clean.obj --json out/fandisk-denoised.metrics.json
echo
echo "denoised mesh: out/fandisk-denoised.ply   metrics: out/fandisk-denoised.metrics.json"
