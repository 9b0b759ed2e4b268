#!/usr/bin/env bash
# Builds rtuscope with AddressSanitizer + UndefinedBehaviorSanitizer and warnings as errors,
# then runs every test (unit, golden, tools, Wireshark, serial) on both cores.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake --preset asan "${launcher[@]}"
cmake --build --preset asan
ctest --preset asan
