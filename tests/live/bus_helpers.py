"""What the live tests share: failing with a message, virtual-bus endpoints, stopping the
processes a test started. The Modbus CRC is tools/pylib/modbus_crc.py."""
import os
import signal
import subprocess
import sys
import tty

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402,F401  (after the path line; used by the tests)


def open_endpoint(path):
    """A virtual-bus endpoint opened raw, for writing frames onto the bus."""
    fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
    tty.setraw(fd)
    return fd


def stop_all(procs):
    """SIGTERM to each process still running (last started first), SIGKILL if it hangs."""
    for p in reversed(procs):
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
