#!/usr/bin/env bash
# Checks that every #include in src/ follows the data: a module may include itself and the
# modules before it in this order, never one after it.
#   core → serial → capture → framing → modbus → pairing → dissect → report → pipeline → app
# Prints each include that runs against the order and exits 1 if there is any.
set -euo pipefail
src="${1:-$(dirname "$0")/../src}"
order=(core serial capture framing modbus pairing dissect report pipeline app)
status=0
for i in "${!order[@]}"; do
  module=${order[$i]}
  [[ -d "$src/$module" ]] || continue
  for later in "${order[@]:$((i + 1))}"; do
    if grep -rn "#include \"$later/" "$src/$module"; then status=1; fi
  done
done
# Every folder under src/ must have its place in the order.
for dir in "$src"/*/; do
  name=$(basename "$dir")
  if [[ ! " ${order[*]} " == *" $name "* ]]; then
    echo "$src/$name: not in the layer order of $(basename "$0")"
    status=1
  fi
done
exit $status
