#!/usr/bin/python3
"""A Modbus RTU slave on Debian's pymodbus (an implementation independent of rtuscope).

usage: pymodbus_slave.py PORT SLAVE_ID BAUD PARITY STOP_BITS
PARITY is N on a pseudo-terminal: pyserial sets parity with a tcsetattr that a pty refuses
(EINVAL), and pymodbus 3.0 then never opens the port (a pty has no parity anyway).
Serves holding/input registers and coils/discrete inputs until SIGTERM.
"""
import logging
import os
import signal
import sys

from pymodbus.datastore import (ModbusSequentialDataBlock, ModbusServerContext,
                                ModbusSlaveContext)
from pymodbus.framer.rtu_framer import ModbusRtuFramer
from pymodbus.server import StartSerialServer


def main():
    port, slave_id, baud, parity, stop = sys.argv[1:6]
    logging.basicConfig(level=logging.ERROR)
    store = ModbusSlaveContext(
        di=ModbusSequentialDataBlock(0, [i % 2 == 0 for i in range(200)]),
        co=ModbusSequentialDataBlock(0, [i % 3 == 0 for i in range(200)]),
        hr=ModbusSequentialDataBlock(0, [1000 + i for i in range(200)]),
        ir=ModbusSequentialDataBlock(0, [2000 + i for i in range(200)]),
        zero_mode=True)
    context = ModbusServerContext(slaves={int(slave_id): store}, single=False)
    # Leave at once: raising SystemExit inside asyncio's write callback makes it loop on
    # "Write buffer should not be empty".
    signal.signal(signal.SIGTERM, lambda *_: os._exit(0))
    print("ready", flush=True)
    StartSerialServer(context=context, framer=ModbusRtuFramer, port=port,
                      baudrate=int(baud), parity=parity, stopbits=int(stop), bytesize=8,
                      timeout=0.005)


if __name__ == "__main__":
    main()
