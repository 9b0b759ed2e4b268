#!/bin/sh
# Rewrites captures/sigrok_*.csv from the original sigrok example dumps, with the exact
# settings recorded in captures/README.md ("Real captures"). Run from the top of the source
# tree with the path of a sigrok-dumps checkout (the public sigrok capture repository):
#
#   tools/import/import_sigrok_dumps.sh PATH/TO/sigrok-dumps
#
# Needs sigrok-cli (Debian package sigrok-cli). The line settings were found from the
# recordings themselves (bit times, parity checks, CRCs); see the README for each capture.
set -eu

dumps=${1:?usage: import_sigrok_dumps.sh PATH/TO/sigrok-dumps}
conv=tools/import/sigrok_uart_capture.py
out=captures
mkdir -p "$out"

# RS-485 slave board: one probe on the bus wire itself (both directions, undriven gaps).
"$conv" "$dumps/uart/modbus_rtu/wizmodbus/wizmodbus.sr" --channel BA+ \
  --baud 9600 --parity N --stop 1 --format csv -o "$out/sigrok_wizmodbus_bus.csv"
# The same session seen at the slave's transceiver: receiver output RX and UART TX merged.
"$conv" "$dumps/uart/modbus_rtu/wizmodbus/wizmodbus.sr" --channel RX --channel TX \
  --baud 9600 --parity N --stop 1 --format csv -o "$out/sigrok_wizmodbus_rxtx.csv"
# Flow meter (slave 247) polled on a half-duplex line, one probe for both directions.
"$conv" "$dumps/uart/modbus_rtu/flowmeter/flowmeter_target_0liter_per_min.sr" --channel RXTX \
  --baud 9600 --parity N --stop 2 --format csv -o "$out/sigrok_flowmeter_0lpm.csv"
# PC side (RS-232 levels, hence --invert) of an RS-232/RS-485 converter: channel 1 is the
# PC's TX (requests), channel 0 its RX (responses).
"$conv" "$dumps/uart/modbus_rtu/brainchild_io_16do/brainchild-io-16do.sr" --channel 1 --channel 0 \
  --invert --baud 19200 --parity E --stop 1 --format csv -o "$out/sigrok_brainchild_io16do.csv"
