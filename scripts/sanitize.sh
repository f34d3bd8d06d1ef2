#!/usr/bin/env bash
# Builds everything with clang, AddressSanitizer + UndefinedBehaviorSanitizer (CMake preset asan-ubsan; the
# same build holds the fuzz harnesses) and runs every unit test under them: any invalid memory access or
# undefined behaviour fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset asan-ubsan > build-asan.log 2>&1 || { tail -30 build-asan.log >&2; exit 1; }
cmake --build --preset asan-ubsan -j"$(nproc)" >> build-asan.log 2>&1 || { tail -30 build-asan.log >&2; exit 1; }
ctest --preset asan-ubsan -j"$(nproc)"
