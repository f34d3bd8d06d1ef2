#!/usr/bin/env bash
# Installs the Debian packages (if missing) and builds scanmesh in Release mode into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
