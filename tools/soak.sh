#!/usr/bin/env bash
# Soak test: rtuscope live on a virtual bus with simulated traffic and rotation, for DURATION
# (e.g. 2m, 2h). Samples RSS, open files and CPU every minute and fails if RSS grows past its
# first-10-minutes level plus 10%, if files leak, or if a played byte is missing from the
# recordings. Usage: tools/soak.sh [DURATION] [BUILD_DIR] [-- more soak.py options]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
duration="${1:-2m}"
build="${2:-$here/../build}"
shift $(( $# > 2 ? 2 : $# ))
[[ "${1:-}" == "--" ]] && shift
exec python3 "$here/soak/soak.py" --duration "$duration" --rtuscope "$build/rtuscope" \
  --vbus "$build/rtuvbus" --rtusim "$build/rtusim" "$@"
