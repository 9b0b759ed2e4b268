#!/usr/bin/env bash
# tools/check-layers.sh must reject an include that runs upward and a folder with no layer,
# and accept a tree that follows the order.
set -euo pipefail
check="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/src/core" "$tmp/src/dissect" "$tmp/src/report"
echo '#include "core/a.hpp"' > "$tmp/src/dissect/b.hpp"
echo '#include "dissect/b.hpp"' > "$tmp/src/report/c.hpp"
bash "$check" "$tmp/src" || { echo "a clean tree was rejected"; exit 1; }
echo '#include "report/c.hpp"' > "$tmp/src/dissect/d.cpp"
if bash "$check" "$tmp/src" > "$tmp/out"; then echo "dissect -> report was accepted"; exit 1; fi
grep -q 'dissect/d.cpp' "$tmp/out" || { echo "the offending include was not named"; exit 1; }
rm "$tmp/src/dissect/d.cpp"
mkdir "$tmp/src/misc"
if bash "$check" "$tmp/src" > "$tmp/out"; then echo "a folder outside the order was accepted"; exit 1; fi
echo ok
