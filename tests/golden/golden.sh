#!/bin/sh
# One golden case, run from the top of the source tree. Shared by the tests (check, coverage)
# and by tools/update-golden.sh (update), so both run exactly the same command:
#   rtuscope decode captures/<name>.<ext> --format text|jsonl [options from captures/<name>.args]
#
#   golden.sh check    RTUSCOPE CAPTURE FORMAT EXPECTED   decode and diff with EXPECTED
#   golden.sh update   RTUSCOPE CAPTURE FORMAT EXPECTED   decode and write EXPECTED
#   golden.sh coverage                                    every capture has an expected file
set -u

captures_of() {
  # Capture files in captures/: the known extensions, minus expected outputs.
  for f in captures/*.hex captures/*.txt captures/*.csv captures/*.pcap captures/*.pcapng; do
    case "$f" in
      *'*'* | *.expected.txt) ;;
      *) [ -f "$f" ] && echo "$f" ;;
    esac
  done
}

if [ "${1:-}" = coverage ]; then
  if [ -z "$(ls captures/*.expected.* 2>/dev/null)" ]; then
    echo "golden: no expected outputs in captures/ yet; nothing to check" >&2
    exit 77  # reported as skipped
  fi
  missing=0
  for capture in $(captures_of); do
    name=${capture%.*}
    if [ ! -f "$name.expected.txt" ] && [ ! -f "$name.expected.jsonl" ]; then
      echo "golden: $capture has no $name.expected.txt or .expected.jsonl;" \
        "create them with: tools/update-golden.sh $capture" >&2
      missing=1
    fi
  done
  exit $missing
fi

if [ $# -ne 5 ]; then
  echo "usage: golden.sh check|update RTUSCOPE CAPTURE FORMAT EXPECTED | golden.sh coverage" >&2
  exit 2
fi
mode=$1 rtuscope=$2 capture=$3 format=$4 expected=$5

if [ -z "$capture" ] || [ ! -f "$capture" ]; then
  echo "golden: no capture for $expected (looked for ${expected%.expected.*}.{hex,txt,csv,pcap,pcapng})" >&2
  exit 1
fi
# Extra options, one line, split on blanks (no quoting).
args=""
args_file="${capture%.*}.args"
if [ -f "$args_file" ]; then
  args=$(head -n 1 "$args_file")
fi

actual=$(mktemp) || exit 1
errors=$(mktemp) || exit 1
trap 'rm -f "$actual" "$errors"' EXIT
# shellcheck disable=SC2086  # the options are meant to split
"$rtuscope" decode "$capture" --format "$format" $args >"$actual" 2>"$errors"
status=$?
if [ $status -ne 0 ]; then
  echo "golden: 'rtuscope decode $capture --format $format $args' exited with $status:" >&2
  cat "$errors" >&2
  exit 1
fi

case "$mode" in
  update)
    cp "$actual" "$expected"
    ;;
  check)
    if ! diff -u --label "$expected (expected)" --label "decode output (actual)" "$expected" "$actual"; then
      echo "golden: output differs from $expected. If the change is intended, run" \
        "tools/update-golden.sh and review the git diff." >&2
      exit 1
    fi
    ;;
  *)
    echo "golden: unknown mode '$mode'" >&2
    exit 2
    ;;
esac
