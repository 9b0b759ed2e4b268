#!/usr/bin/env bash
# Accuracy benchmark: simulated traffic with exact ground truth, decoded by rtuscope, scored
# by score.py. Configurations: {per-byte, USB-chunked, idle-flush} × {clean, 5% faults} ×
# {9600, 19200, 115200 baud}, several seeds each (idle-flush: an adapter that sends once the
# line has been idle 4 character times, in packets of up to 32 bytes, as CH34x-like chips and
# a UART's character timeout deliver). A configuration passes at ≥ 99.9% frame recall and
# precision when clean and ≥ 99% with faults, with every byte accounted for.
#
#   tools/accuracy/run.sh [BUILD_DIR]     (default: build, a Release build)
#   SEEDS="1 2 3" TRANSACTIONS=2000 FAULT_RATE=0.05 KEEP=dir tools/accuracy/run.sh
#
# PROFILE=heavy runs the sick-bus profile instead (rtusim --profile heavy: 10% of the
# transactions faulty, damage in any byte, noise touching frames, glitch bytes, early
# responses, absent slaves; see tools/sim/fault_injector.hpp): {per-byte, USB-chunked,
# idle-flush} × {9600, 19200, 115200}, 4 seeds, target 99%. Each USB seed gets its own
# adapter: latency timer and packet size from USB_ADAPTERS (ms:bytes, taken in turn); each
# idle-flush seed its idle wait and packet size from IDLE_ADAPTERS (character times:bytes).
# Every heavy run is
# also decoded by ref_decoder.py (a small CRC-resync decoder, the baseline; REFERENCE=0
# skips it), and misses.py sorts the frames rtuscope missed into classes (MISSES=0 skips).
#
# To see what a configuration got wrong: KEEP=dir, then
#   tools/accuracy/score.py dir/usb_faults_9600_s1.truth.jsonl dir/usb_faults_9600_s1.decoded.jsonl --show 10
#   tools/accuracy/misses.py dir/usb_heavy_9600_s1.truth.jsonl dir/usb_heavy_9600_s1.decoded.jsonl
#
# A benchmark, not a test: it prints a table and "accuracy: N passed, M failed", and exits 1
# when a configuration fails.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
profile=${PROFILE:-classic}
transactions=${TRANSACTIONS:-2000}
fault_rate=${FAULT_RATE:-0.05}
case $profile in
  classic)
    seeds=${SEEDS:-1 2 3}
    modes="clean faults"
    reference=${REFERENCE:-0}
    misses=${MISSES:-0}
    ;;
  heavy)
    seeds=${SEEDS:-1 2 3 4}
    modes="heavy"
    reference=${REFERENCE:-1}
    misses=${MISSES:-1}
    # Latency timers of 1-16 ms and packets of 4-62 data bytes (FTDI: 62 of 64; small
    # packets stand for adapters and drivers that hand over a few bytes at a time).
    read -r -a usb_adapters <<<"${USB_ADAPTERS:-16:62 1:4 4:16 8:32 2:8 12:48}"
    # Adapters that send once the line is idle (idle character times:packet bytes).
    read -r -a idle_adapters <<<"${IDLE_ADAPTERS:-4:32 1.5:32 8:62 2:16}"
    ;;
  *)
    echo "run.sh: PROFILE is classic or heavy, not '$profile'" >&2
    exit 2
    ;;
esac

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
ref_manifest=$work/reference.tsv
: >"$manifest"
: >"$ref_manifest"

for chunking in perbyte usb idle; do
  for mode in $modes; do
    for baud in 9600 19200 115200; do
      case $mode in
        clean) sim_args=(--faults 0); target=0.999 ;;
        faults) sim_args=(--faults "$fault_rate"); target=0.99 ;;
        heavy) sim_args=(--profile heavy); target=0.99 ;;
      esac
      label="$chunking $mode $baud"
      n=0
      for seed in $seeds; do
        base=$work/${chunking}_${mode}_${baud}_s$seed
        usb_args=()
        if [ "$mode" = heavy ] && [ "$chunking" = usb ]; then
          adapter=${usb_adapters[$((n % ${#usb_adapters[@]}))]}
          usb_args=(--latency-ms "${adapter%%:*}" --packet "${adapter##*:}")
        elif [ "$mode" = heavy ] && [ "$chunking" = idle ]; then
          adapter=${idle_adapters[$((n % ${#idle_adapters[@]}))]}
          usb_args=(--idle-chars "${adapter%%:*}" --packet "${adapter##*:}")
        elif [ "$chunking" = idle ]; then
          usb_args=(--idle-chars 4 --packet 32)
        fi
        n=$((n + 1))
        # Each baud rate gets its own traffic; per-byte and USB runs share theirs.
        "$build/rtusim" --seed "$((seed * 1000000 + baud))" --transactions "$transactions" \
          --baud "$baud" "${sim_args[@]}" --chunking "$chunking" "${usb_args[@]}" \
          --out "$base.hex" --truth "$base.truth.jsonl"
        if ! "$build/rtuscope" decode "$base.hex" --format jsonl >"$base.decoded.jsonl" \
          2>"$base.err"; then
          echo "run.sh: rtuscope decode failed on $label seed $seed: $(head -c 300 "$base.err")" >&2
        fi
        printf '%s\t%s\t%s\t%s\n' "$label" "$target" "$base.truth.jsonl" "$base.decoded.jsonl" \
          >>"$manifest"
        if [ "$reference" = 1 ]; then
          python3 "$here/ref_decoder.py" "$base.hex" >"$base.ref.jsonl"
          printf '%s\t%s\t%s\t%s\n' "$label reference" "$target" "$base.truth.jsonl" \
            "$base.ref.jsonl" >>"$ref_manifest"
        fi
      done
    done
  done
done

if [ "$profile" = heavy ]; then
  echo "rtusim --profile heavy --transactions $transactions, seeds: $seeds;" \
    "USB adapters (latency ms:packet bytes) by seed: ${usb_adapters[*]}"
else
  echo "rtusim --transactions $transactions --faults 0|$fault_rate, seeds: $seeds"
fi
status=0
python3 "$here/score.py" --manifest "$manifest" || status=1
if [ "$reference" = 1 ]; then
  echo
  echo "reference decoder (ref_decoder.py), same captures:"
  python3 "$here/score.py" --manifest "$ref_manifest" || true
fi
if [ "$misses" = 1 ]; then
  echo
  python3 "$here/misses.py" --manifest "$manifest" --examples 0
fi
exit $status
