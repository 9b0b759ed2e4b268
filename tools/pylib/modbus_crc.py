"""CRC-16/MODBUS for the Python tools and tests, written once.

Modbus RTU ends every frame (ADU) with a CRC-16: polynomial 0x8005 bit-reversed (0xA001),
initial value 0xFFFF, no final xor, sent low byte first (MODBUS over Serial Line V1.02,
§2.5.1.2 and §6.2.2). It is written out here independently of the C++ one
(src/core/crc16.cpp), so that a test that checks rtuscope does not reuse rtuscope's code.

Two functions, because scripts want two different things and once called both `crc16`:

  crc16(data) -> int       the CRC value. Over a whole intact ADU, CRC included, it is 0,
                           which is how a received frame is checked: crc16(adu) == 0.
  with_crc(data) -> bytes  the ADU: `data` followed by its CRC, low byte first, ready to be
                           written on a bus or into a capture.

Scripts find this folder with one sys.path line relative to their own file, so they run
from any working directory (CTest's or a user's) without installing anything. Standard
library only.
"""

CRC_INIT = 0xFFFF


def _table():
    """Each byte value's eight shift-and-xor steps done once, so crc16 takes a byte a step."""
    table = []
    for n in range(256):
        c = n
        for _ in range(8):
            c = (c >> 1) ^ 0xA001 if c & 1 else c >> 1
        table.append(c)
    return table


_TABLE = _table()


def crc16(data, crc=CRC_INIT):
    """The CRC-16/MODBUS of `data` (bytes or ints 0-255) as an int.

    `crc` continues a CRC already run over the bytes before `data`, for a caller that
    extends a frame a few bytes at a time (tools/accuracy/ref_decoder.py's search).
    """
    for b in data:
        crc = (crc >> 8) ^ _TABLE[(crc ^ b) & 0xFF]
    return crc


def with_crc(data):
    """The ADU for `data` (bytes or ints 0-255): its bytes, then their CRC, low byte first."""
    data = bytes(data)
    crc = crc16(data)
    return data + bytes([crc & 0xFF, crc >> 8])
