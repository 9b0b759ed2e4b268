#!/bin/sh
# Capture warnings on stderr, as a user meets them: each printed exactly once per command
# (`report` reads the file twice, identifying slaves first), as "rtuscope: warning: FILE: ...",
# and none for a capture whose settings are declared and agree with its timing.
#   warnings_once.sh RTUSCOPE     (run from the top of the source tree)
set -u
rtuscope=$1
errors=$(mktemp) || exit 1
trap 'rm -f "$errors"' EXIT
failed=0

# expect COUNT PATTERN ARGS...: `rtuscope ARGS` prints COUNT warnings, PATTERN (if any) in one.
expect() {
  count=$1 pattern=$2
  shift 2
  if ! "$rtuscope" "$@" >/dev/null 2>"$errors"; then
    echo "FAIL: rtuscope $* exited with an error:" >&2
    cat "$errors" >&2
    failed=1
    return
  fi
  found=$(grep -c '^rtuscope: warning: ' "$errors")
  if [ "$found" -ne "$count" ] || { [ -n "$pattern" ] && ! grep -qF -- "$pattern" "$errors"; }; then
    echo "FAIL: rtuscope $*: expected $count warning(s) with '$pattern', stderr was:" >&2
    cat "$errors" >&2
    failed=1
    return
  fi
  echo "ok: rtuscope $*"
}

wrong=captures/wrong_baud_19200_as_9600.hex
expect 1 "rtuscope: warning: $wrong: bytes arrive 0.573 ms apart" decode "$wrong" --baud 9600
expect 1 "decode with --baud 19200" decode "$wrong" --baud 9600 --format jsonl
expect 1 "decode with --baud 19200" report "$wrong" --baud 9600
expect 0 "" decode "$wrong"

foreign=captures/device_examples_saleae_table.csv
# It declares no settings, but each byte has its timestamp: they are inferred, said once.
expect 1 "$foreign: line settings inferred from the byte timing: 9600 8E1" decode "$foreign"
expect 1 "line settings inferred from the byte timing: 9600 8E1" report "$foreign" --format json
expect 0 "" decode "$foreign" --baud 9600 --parity E --stop 1
exit $failed
