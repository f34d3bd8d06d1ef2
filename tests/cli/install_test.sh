#!/usr/bin/env bash
# cmake --install into a temporary prefix, then run the installed scanmesh from another folder: the light
# commands, and one that it hands to scanmesh-full (installed under libexec/scanmesh/).
set -euo pipefail
build=$1
data=$2
prefix=$(mktemp -d)
work=$(mktemp -d)
trap 'rm -rf "$prefix" "$work"' EXIT
cmake --install "$build" --prefix "$prefix" > /dev/null
cd "$work"
"$prefix/bin/scanmesh" version
"$prefix/bin/scanmesh" denoise "$data/fandisk-noisy.obj" out.ply --iterations 5 -q
test -s out.ply
"$prefix/bin/scanmesh" mesh "$data/bun0.pcd" bun0.ply -q
test -s bun0.ply
test -x "$prefix/libexec/scanmesh/scanmesh-full"
test -f "$prefix/share/scanmesh/configs/scan_to_mesh.yaml"
echo "installed tool ok"
