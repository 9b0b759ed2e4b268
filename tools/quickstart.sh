#!/usr/bin/env bash
# Installs what rtuscope needs (Debian 12), builds it in Release, and runs the demo (a
# virtual RS-485 bus with simulated devices, sniffed live; no hardware needed).
# Run as root or with sudo: sudo bash tools/quickstart.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRTUSCOPE_TESTS=OFF
cmake --build build -j2
# The demo: a virtual RS-485 bus with the four simulated devices, sniffed live.
echo "== rtuscope demo"
build/rtuscope demo
