#!/usr/bin/env bash
# Side-by-side speed of rtuscope and tshark on the same simulated frames.
#
#   tools/bench/compare.sh [FRAMES] [WORK_DIR]
#
# The simulator writes FRAMES frames (default 5,000,000) of 19200-baud polling traffic twice:
# one byte per line (a logic analyser's view) and in USB adapter reads. The USB reads are
# also written as a live recording holds them (recording.pcapng: one raw-read record per read
# of 1-62 bytes, rtusim --pcapng). From the USB capture rtuscope writes its native export
# (native.pcapng: the raw reads plus the decoded frames, as `export --raw` holds them) and a
# classic pcap of LINKTYPE 252 frames for tshark. Then each command runs RUNS times (default
# 3), and a Markdown table gives the least wall time, frames per second, the ratio to tshark
# and the largest peak RSS. tshark runs with its default preferences (its fastest: CRC
# checking off). Each pcapng's report runs once more on one core (taskset): the speed target
# for a live recording is set there. Use a Release build (cmake --preset release).
# The captures stay in WORK_DIR (default: a new temporary folder, removed at the end).
#
# A second table does the same for adversarial traffic: RANDOM_FRAMES frames (default
# 200,000; 0 leaves it out) with a random slave, function code and 0-60 data bytes, each
# CRC-valid (tools/bench/random_frames.py), read per byte and a read per frame. There every
# byte may start a frame of no known length, which ordinary polling never asks of the framer.
set -euo pipefail
cd "$(dirname "$0")/../.."

frames=${1:-5000000}
work=${2:-}
rtuscope=${RTUSCOPE:-build/rtuscope}
rtusim=${RTUSIM:-build/rtusim}
for tool in "$rtuscope" "$rtusim"; do
  [[ -x $tool ]] || { echo "compare.sh: $tool not built (cmake --preset release && cmake --build build)" >&2; exit 2; }
done
command -v tshark >/dev/null || { echo "compare.sh: tshark not installed" >&2; exit 2; }
if [[ -z $work ]]; then
  work=$(mktemp -d "${TMPDIR:-/tmp}/rtuscope-bench.XXXXXX")
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"

transactions=$((frames / 2))
echo "Making captures of $frames frames in $work ..." >&2
"$rtusim" --transactions "$transactions" --baud 19200 --chunking perbyte --seed 1 \
  --out "$work/perbyte.hex" >/dev/null
"$rtusim" --transactions "$transactions" --baud 19200 --chunking usb --seed 1 \
  --out "$work/usb.hex" --pcapng "$work/recording.pcapng" >/dev/null
"$rtuscope" export "$work/usb.hex" --raw -o "$work/native.pcapng" -q 2>/dev/null
"$rtuscope" export "$work/usb.hex" -o "$work/frames.pcap" -q 2>/dev/null
# Every capture holds the same frames; the report says how many.
count=$("$rtuscope" report "$work/usb.hex" --format json --no-identify -q |
  python3 -c 'import json,sys; print(json.load(sys.stdin)["totals"]["frames"])')

# The models report identifies in this traffic, named as a user who knows the devices would
# name them: the report with them named decodes the same registers without identifying, so
# the difference to the plain report is what identification itself costs.
named=$("$rtuscope" report "$work/usb.hex" --format json -q |
  python3 -c 'import json,sys
for addr, s in json.load(sys.stdin)["slaves"].items():
    if s.get("device_model_source") == "identified": print("--device", addr + "=" + s["device"])')
read -r -a named <<<"$(echo $named)"

# The captures just written are still being flushed to disk: let that not slow the first runs.
sync

# run LABEL INPUT COMMAND...: prints "label|input|wall|rss_kb", the least wall time and the
# largest peak RSS of RUNS runs (default 3): one run alone is at the mercy of whatever else
# the machine does.
run() {
  local label=$1 input=$2 best="" rss=0 i wall kb
  shift 2
  for ((i = 0; i < ${RUNS:-3}; i++)); do
    /usr/bin/time -o "$work/time.txt" -f "%e %M" "$@" >/dev/null 2>"$work/stderr.txt" || {
      echo "compare.sh: $* failed: $(tail -3 "$work/stderr.txt")" >&2
      exit 1
    }
    read -r wall kb < <(tail -1 "$work/time.txt")
    if [[ -z $best ]] || python3 -c "import sys; sys.exit(not $wall < $best)"; then best=$wall; fi
    ((kb > rss)) && rss=$kb
  done
  echo "$label|$input|$best $rss"
}

results=()
results+=("$(run "tshark -T fields (unit id, function code)" "frames.pcap" \
  tshark -n -r "$work/frames.pcap" -T fields -e frame.number -e mbrtu.unit_id \
  -e modbus.func_code)")
for input in recording.pcapng native.pcapng perbyte.hex usb.hex; do
  results+=("$(run "rtuscope report --format json" "$input" \
    "$rtuscope" report "$work/$input" --format json -o /dev/null -q)")
  # The speed target for a live recording is set on one core (tshark uses one too).
  if [[ $input == *.pcapng ]] && command -v taskset >/dev/null; then
    results+=("$(run "rtuscope report --format json, one core (taskset -c 0)" "$input" \
      taskset -c 0 "$rtuscope" report "$work/$input" --format json -o /dev/null -q)")
  fi
  results+=("$(run "rtuscope report, models named (--device)" "$input" \
    "$rtuscope" report "$work/$input" --format json --no-identify "${named[@]}" -o /dev/null -q)")
  results+=("$(run "rtuscope report --no-identify" "$input" \
    "$rtuscope" report "$work/$input" --format json --no-identify -o /dev/null -q)")
  results+=("$(run "rtuscope decode --format jsonl" "$input" \
    "$rtuscope" decode "$work/$input" --format jsonl -o /dev/null -q)")
  results+=("$(run "rtuscope export" "$input" \
    "$rtuscope" export "$work/$input" -o "$work/out.pcapng" -q)")
done

# table FRAMES RESULT...: a Markdown table of run results, the first of them tshark's.
table() {
  local frames=$1 r label input stats wall rss tshark_wall
  shift
  tshark_wall=$(cut -d'|' -f3 <<<"$1" | cut -d' ' -f1)
  echo "| run | input | wall s | frames/s | × tshark | peak RSS MB |"
  echo "|---|---|---|---|---|---|"
  for r in "$@"; do
    IFS='|' read -r label input stats <<<"$r"
    read -r wall rss <<<"$stats"
    python3 - "$label" "$input" "$wall" "$rss" "$frames" "$tshark_wall" <<'EOF'
import sys
label, input_, wall, rss, count, tshark = sys.argv[1:]
wall, rss, count, tshark = float(wall), int(rss), int(count), float(tshark)
rate = count / wall if wall > 0 else float("inf")
ratio = tshark / wall if wall > 0 else float("inf")
print(f"| {label} | {input_} | {wall:.2f} | {rate / 1e6:.2f} M | {ratio:.1f} | {rss / 1024:.0f} |")
EOF
  done
}

size_of() { du -m "$work/$1" | cut -f1; }
echo
echo "$count frames; captures: per-byte hex $(size_of perbyte.hex) MB, USB hex $(size_of usb.hex) MB," \
  "recording $(size_of recording.pcapng) MB, native export $(size_of native.pcapng) MB, pcap 252 $(size_of frames.pcap) MB; $(nproc) cores"
echo
table "$count" "${results[@]}"

random_frames=${RANDOM_FRAMES:-200000}
((random_frames > 0)) || exit 0
echo "Making captures of $random_frames random frames in $work ..." >&2
python3 tools/bench/random_frames.py "$random_frames" "$work/random_perbyte.hex" --per-byte
python3 tools/bench/random_frames.py "$random_frames" "$work/random_reads.hex"
# tshark reads the frames that rtuscope finds in the per-byte capture (nearly all of them).
"$rtuscope" export "$work/random_perbyte.hex" -o "$work/random.pcap" -q 2>/dev/null
sync
random_results=()
random_results+=("$(run "tshark -T fields (unit id, function code)" "random.pcap" \
  tshark -n -r "$work/random.pcap" -T fields -e frame.number -e mbrtu.unit_id \
  -e modbus.func_code)")
for input in random_perbyte.hex random_reads.hex; do
  random_results+=("$(run "rtuscope report --format json" "$input" \
    "$rtuscope" report "$work/$input" --format json -o /dev/null -q)")
  random_results+=("$(run "rtuscope decode --format jsonl" "$input" \
    "$rtuscope" decode "$work/$input" --format jsonl -o /dev/null -q)")
  random_results+=("$(run "rtuscope export" "$input" \
    "$rtuscope" export "$work/$input" -o "$work/out.pcapng" -q)")
done
echo
echo "$random_frames random frames (frames/s counts them all); captures: per-byte hex" \
  "$(size_of random_perbyte.hex) MB, a read per frame $(size_of random_reads.hex) MB," \
  "pcap 252 $(size_of random.pcap) MB"
echo
table "$random_frames" "${random_results[@]}"
