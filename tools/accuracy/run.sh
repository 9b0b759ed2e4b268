#!/usr/bin/env bash
# Accuracy benchmark: simulated traffic with exact ground truth, decoded by rtuscope, scored
# by score.py. Configurations: {per-byte, USB-chunked} × {clean, 5% faults} × {9600, 19200,
# 115200 baud}, several seeds each. A configuration passes at ≥ 99.9% frame recall and
# precision when clean and ≥ 99% with faults, with every byte accounted for.
#
#   tools/accuracy/run.sh [BUILD_DIR]     (default: build, a Release build)
#   SEEDS="1 2 3" TRANSACTIONS=2000 FAULT_RATE=0.05 KEEP=dir tools/accuracy/run.sh
#
# To see what a configuration got wrong: KEEP=dir, then
#   tools/accuracy/score.py dir/usb_faults_9600_s1.truth.jsonl dir/usb_faults_9600_s1.decoded.jsonl --show 10
#
# A benchmark, not a test: it prints a table and "accuracy: N passed, M failed", and exits 1
# when a configuration fails.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
seeds=${SEEDS:-1 2 3}
transactions=${TRANSACTIONS:-2000}
fault_rate=${FAULT_RATE:-0.05}

for tool in rtusim rtuscope; do
  if [ ! -x "$build/$tool" ]; then
    echo "run.sh: $build/$tool not found; build first:" >&2
    echo "  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build -j2" >&2
    exit 2
  fi
done

if [ -n "${KEEP:-}" ]; then
  work=$KEEP
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
manifest=$work/manifest.tsv
: >"$manifest"

for chunking in perbyte usb; do
  for mode in clean faults; do
    for baud in 9600 19200 115200; do
      if [ "$mode" = clean ]; then rate=0; target=0.999; else rate=$fault_rate; target=0.99; fi
      label="$chunking $mode $baud"
      for seed in $seeds; do
        base=$work/${chunking}_${mode}_${baud}_s$seed
        # Each baud rate gets its own traffic; per-byte and USB runs share theirs.
        "$build/rtusim" --seed "$((seed * 1000000 + baud))" --transactions "$transactions" \
          --baud "$baud" \
          --faults "$rate" --chunking "$chunking" --out "$base.hex" --truth "$base.truth.jsonl"
        if ! "$build/rtuscope" decode "$base.hex" --format jsonl >"$base.decoded.jsonl" \
          2>"$base.err"; then
          echo "run.sh: rtuscope decode failed on $label seed $seed: $(head -c 300 "$base.err")" >&2
        fi
        printf '%s\t%s\t%s\t%s\n' "$label" "$target" "$base.truth.jsonl" "$base.decoded.jsonl" \
          >>"$manifest"
      done
    done
  done
done

echo "rtusim --transactions $transactions --faults 0|$fault_rate, seeds: $seeds"
python3 "$here/score.py" --manifest "$manifest"
