#!/bin/sh
# Regenerates the reviewed expected outputs of the golden tests, in one command:
#
#   tools/update-golden.sh                   every captures/<name>.expected.{txt,jsonl} there is
#   tools/update-golden.sh captures/x.hex    (also) both expected files of these captures
#
# It builds rtuscope first (build dir: $RTUSCOPE_BUILD_DIR, else build-asan or build, whichever
# exists), then runs the same command as the tests (tests/golden/golden.sh). Review the result
# with `git diff captures/` before committing; never edit expected files by hand.
set -eu
cd "$(dirname "$0")/.."

build_dir=${RTUSCOPE_BUILD_DIR:-}
if [ -z "$build_dir" ]; then
  for d in build-asan build; do
    if [ -f "$d/CMakeCache.txt" ]; then build_dir=$d; break; fi
  done
fi
if [ -z "$build_dir" ]; then
  echo "update-golden: no build directory; configure one first (cmake --preset asan)" >&2
  exit 2
fi
cmake --build "$build_dir" --target rtuscope
rtuscope=$build_dir/rtuscope

update() {  # capture format expected
  sh tests/golden/golden.sh update "$rtuscope" "$1" "$2" "$3"
  echo "wrote $3"
}

capture_for() {  # name → capture path, or nothing
  for ext in hex txt csv pcap pcapng; do
    if [ -f "$1.$ext" ]; then echo "$1.$ext"; return; fi
  done
}

for capture in "$@"; do
  name=${capture%.*}
  update "$capture" text "$name.expected.txt"
  update "$capture" jsonl "$name.expected.jsonl"
done
if [ $# -eq 0 ]; then
  for expected in captures/*.expected.txt captures/*.expected.jsonl; do
    [ -f "$expected" ] || continue
    name=${expected%.expected.*}
    case "$expected" in *.jsonl) format=jsonl ;; *) format=text ;; esac
    capture=$(capture_for "$name")
    if [ -z "$capture" ]; then
      echo "update-golden: $expected has no capture $name.{hex,txt,csv,pcap,pcapng}" >&2
      exit 1
    fi
    update "$capture" "$format" "$expected"
  done
fi
