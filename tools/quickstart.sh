#!/usr/bin/env bash
# Installs what rtuscope needs (Debian 12), builds it in Release, and decodes the bundled
# sample capture. Run as root or with sudo: sudo bash tools/quickstart.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRTUSCOPE_TESTS=OFF
cmake --build build -j2
demo=captures/device_examples.hex
echo "== rtuscope decode $demo"
build/rtuscope decode "$demo"
