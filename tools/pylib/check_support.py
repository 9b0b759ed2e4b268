"""What the Python checks share, written once: failing with a message, and a fresh folder.

A check prints "FAIL: what went wrong" on stderr and exits 1 at its first failure, so CTest
shows the reason in its output. Scripts find this folder with one sys.path line relative to
their own file, as for modbus_crc. Standard library only.
"""
import os
import shutil
import sys


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def fresh_dir(path):
    """`path` as an empty folder (what an earlier run left there is removed)."""
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path
