#!/bin/sh
# The device-example captures are generated, never edited: re-running their generator must give
# the committed files byte for byte. Run from the top of the source tree.
set -u
out=$(mktemp -d) || exit 1
trap 'rm -rf "$out"' EXIT
python3 tools/make_examples_capture.py "$out" || exit 1
status=0
for f in device_examples.hex device_examples_saleae_legacy.csv device_examples_saleae_table.csv; do
  if ! cmp -s "$out/$f" "captures/$f"; then
    echo "captures/$f differs from what tools/make_examples_capture.py writes:" >&2
    diff -u "captures/$f" "$out/$f" | head -n 40 >&2
    status=1
  fi
done
exit $status
