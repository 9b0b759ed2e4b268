#!/usr/bin/env bash
# Makes rtuscope a capture interface of Wireshark (and tshark) for the current user: writes
# a small script, rtuscope-extcap, into Wireshark's personal extcap folder. Wireshark runs
# every program in that folder with extcap arguments only; the script adds the subcommand.
#
#   tools/install-extcap.sh [PATH/TO/rtuscope]      (default: rtuscope on PATH, else ./build)
#   tools/install-extcap.sh --uninstall
#
# The folder: what `tshark -G folders` names "Personal Extcap path" (Wireshark 4.2 and
# later), else "<Personal configuration>/extcap" (4.0 scans it but does not print it),
# else $WIRESHARK_CONFIG_DIR/extcap or $HOME/.config/wireshark/extcap.
set -euo pipefail

personal_extcap_dir() {
  local folders
  if folders=$(tshark -G folders 2>/dev/null); then
    local dir
    dir=$(sed -n 's/^Personal Extcap path:[[:space:]]*//p' <<<"$folders")
    if [[ -n "$dir" ]]; then echo "$dir"; return; fi
    dir=$(sed -n 's/^Personal configuration:[[:space:]]*//p' <<<"$folders")
    if [[ -n "$dir" ]]; then echo "$dir/extcap"; return; fi
  fi
  echo "${WIRESHARK_CONFIG_DIR:-$HOME/.config/wireshark}/extcap"
}

dir=$(personal_extcap_dir)
target="$dir/rtuscope-extcap"

if [[ "${1:-}" == "--uninstall" ]]; then
  rm -f "$target"
  echo "removed $target"
  exit 0
fi

rtuscope="${1:-}"
if [[ -z "$rtuscope" ]]; then
  rtuscope=$(command -v rtuscope || true)
  [[ -n "$rtuscope" ]] || rtuscope="$(dirname "$0")/../build/rtuscope"
fi
if [[ ! -x "$rtuscope" ]]; then
  echo "install-extcap: $rtuscope: no rtuscope program there (build it, or give its path)" >&2
  exit 2
fi
rtuscope=$(realpath "$rtuscope")
if ! "$rtuscope" extcap --extcap-interfaces >/dev/null; then
  echo "install-extcap: $rtuscope: this rtuscope has no working 'extcap' command" >&2
  exit 2
fi

mkdir -p "$dir"
printf '#!/bin/bash\n# Written by rtuscope tools/install-extcap.sh: Wireshark runs this with extcap arguments.\nexec %q extcap "$@"\n' \
  "$rtuscope" >"$target.tmp"
chmod 755 "$target.tmp"
mv "$target.tmp" "$target"
echo "installed $target (runs $rtuscope extcap)"
echo "Wireshark lists a 'Modbus RTU on PORT (rtuscope)' interface per serial port; restart it, or"
echo "press F5 in its capture window. More ports (e.g. a virtual bus): RTUSCOPE_EXTCAP_PORTS=a:b"
