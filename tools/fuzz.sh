#!/usr/bin/env bash
# tools/fuzz.sh TARGET SECONDS [JOBS]: runs the libFuzzer build of one fuzz target
# (build-fuzz/tests/fuzz/fuzz_TARGET; builds nothing) for SECONDS of wall time on a scratch
# copy of its committed corpus (captures/regressions/fuzz/TARGET/), so the corpus in git only
# grows by deliberate adds. TARGET is "pcap" or "fuzz_pcap". JOBS > 1 runs libFuzzer's fork
# mode on that many processes.
#
# Prints the final statistics as a README table row: | target | seconds | executions | coverage |
# RTUSCOPE_FUZZ_BUDGET=cpu makes SECONDS the fuzzer's own CPU time (user + system) instead
# of wall time, so a run on a machine shared with builds still gets its full share; the
# fuzzer is stopped with SIGINT when it has used it (one process only, JOBS = 1).
#
# On a finding it keeps the scratch directory, prints the reproducer's path and how to
# replay it; exits 1. Set RTUSCOPE_FUZZ_KEEP=1 to keep the scratch directory (and the corpus
# the run grew) in any case.
set -euo pipefail
cd "$(dirname "$0")/.."

if [[ $# -lt 2 || $# -gt 3 ]]; then
  echo "usage: tools/fuzz.sh TARGET SECONDS [JOBS]" >&2
  exit 2
fi
name=${1#fuzz_}
seconds=$2
jobs=${3:-1}
if ! [[ $seconds =~ ^[1-9][0-9]*$ && $jobs =~ ^[1-9][0-9]*$ ]]; then
  echo "tools/fuzz.sh: SECONDS and JOBS must be positive integers" >&2
  exit 2
fi
binary=build-fuzz/tests/fuzz/fuzz_$name
corpus=captures/regressions/fuzz/$name
if [[ ! -d $corpus ]]; then
  targets=$(find captures/regressions/fuzz -mindepth 1 -maxdepth 1 -type d -printf '%f ')
  echo "tools/fuzz.sh: no corpus $corpus (targets: $targets)" >&2
  exit 2
fi
if [[ ! -x $binary ]]; then
  echo "tools/fuzz.sh: $binary is missing; build it: cmake --preset fuzz && cmake --build --preset fuzz" >&2
  exit 2
fi

scratch=$(mktemp -d "${TMPDIR:-/tmp}/rtuscope-fuzz-$name.XXXXXX")
mkdir "$scratch/corpus" "$scratch/findings"
cp "$corpus"/* "$scratch/corpus/"

budget=${RTUSCOPE_FUZZ_BUDGET:-wall}
if [[ $budget != wall && $budget != cpu ]] || [[ $budget == cpu && $jobs -gt 1 ]]; then
  echo "tools/fuzz.sh: RTUSCOPE_FUZZ_BUDGET is 'wall' (default) or 'cpu' (with JOBS = 1)" >&2
  exit 2
fi
options=(-timeout=25 -print_final_stats=1 -artifact_prefix="$scratch/findings/")
if [[ $budget == wall ]]; then options+=(-max_total_time="$seconds"); fi
if ((jobs > 1)); then options+=(-fork="$jobs"); fi
status=0
if [[ $budget == wall ]]; then
  "$binary" "${options[@]}" "$scratch/corpus" >"$scratch/fuzz.log" 2>&1 || status=$?
else
  "$binary" "${options[@]}" "$scratch/corpus" >"$scratch/fuzz.log" 2>&1 &
  pid=$!
  ticks=$(getconf CLK_TCK)
  while kill -0 "$pid" 2>/dev/null; do
    sleep 5
    # Fields 14 and 15 of /proc/PID/stat: user and system time in clock ticks.
    used=$(awk -v t="$ticks" '{ print int(($14 + $15) / t) }' "/proc/$pid/stat" 2>/dev/null) || break
    if ((used >= seconds)); then kill -INT "$pid" 2>/dev/null || true; break; fi
  done
  wait "$pid" || status=$?
  # Stopped at its budget: libFuzzer prints its statistics and exits 72.
  if ((status == 72)) && grep -q 'run interrupted' "$scratch/fuzz.log"; then status=0; fi
fi

# The last statistics line: "#N DONE cov: X ft: Y ..." (one process) or "#N: cov: X ft: Y ..."
# (fork mode).
stats=$(grep -E '^#[0-9]+:?[[:space:]]' "$scratch/fuzz.log" | grep -E 'cov: [0-9]+' | tail -n 1 || true)
executions=$(sed -nE 's/^stat::number_of_executed_units: *([0-9]+).*/\1/p' "$scratch/fuzz.log" |
             tail -n 1)
[[ -n $executions ]] || executions=$(sed -nE 's/^#([0-9]+).*/\1/p' <<<"$stats")
cov=$(sed -nE 's/.*cov: ([0-9]+).*/\1/p' <<<"$stats")
ft=$(sed -nE 's/.*ft: ([0-9]+).*/\1/p' <<<"$stats")
echo "$stats"
echo "| fuzz_$name | $seconds | ${executions:-?} | cov ${cov:-?}, ft ${ft:-?} |"

findings=$(find "$scratch/findings" -type f | sort)
if [[ $status -ne 0 || -n $findings ]]; then
  echo "tools/fuzz.sh: fuzz_$name failed (exit $status); log: $scratch/fuzz.log" >&2
  for f in $findings; do
    echo "reproducer: $f" >&2
    echo "  replay: $binary $f" >&2
    echo "  keep: cp $f $corpus/crash-WHAT-IT-IS, with its reason in captures/regressions/fuzz/README.md" >&2
  done
  exit 1
fi
if [[ ${RTUSCOPE_FUZZ_KEEP:-0} == 1 ]]; then
  echo "scratch directory kept: $scratch"
else
  rm -rf "$scratch"
fi
