#!/usr/bin/env bash
# Builds everything (installing Debian packages if missing) and runs the unit tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)"
