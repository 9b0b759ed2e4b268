"""The reads of an `rtuscope live -w` recording (LINKTYPE_RTAC_SERIAL, ns timestamps), as
the sniffer's port gave them: what its timing flags could see and nothing more."""
import struct

SHB, IDB, EPB = 0x0A0D0D0A, 1, 6
LINKTYPE_RTAC_SERIAL = 250
RTAC_HEADER = 12
DATA_EVENTS = {0x01, 0x02, 0x07, 0x08, 0x09, 0x0A}  # bytes, with or without a line error
OPT_COMMENT = 1
READ_LATE = b"read late:"  # how a read the host made late is marked (Chunk::read_late)


def _comments(block, order, at, end):
    while at + 4 <= end:
        code, length = struct.unpack_from(order + "HH", block, at)
        if code == 0:
            break
        if code == OPT_COMMENT:
            yield block[at + 4:at + 4 + length]
        at += 4 + (length + 3) // 4 * 4


def blocks(data):
    """(block type, whole block, byte order) of every whole block; a block cut short (a
    recording stopped while writing it) ends the walk, and what came before it stands."""
    order, at = "<", 0
    while at + 12 <= len(data):
        kind = struct.unpack_from("<I", data, at)[0]  # the section header's reads the same
        if kind == SHB:
            order = "<" if data[at + 8:at + 12] == b"\x4d\x3c\x2b\x1a" else ">"
        length = struct.unpack_from(order + "I", data, at + 4)[0]
        if length < 12 or at + length > len(data):
            return
        yield kind, data[at:at + length], order
        at += length


def read_times(path):
    """[(time in ns, bytes, marked late)] of every read, records of one read joined."""
    with open(path, "rb") as f:
        data = f.read()
    reads = []
    links = []
    for kind, block, order in blocks(data):
        if kind == SHB:
            links = []
        elif kind == IDB:
            links.append(struct.unpack_from(order + "H", block, 8)[0])
        elif kind == EPB:
            if_id, high, low, captured = struct.unpack_from(order + "IIII", block, 8)
            payload = block[28:28 + captured]
            if (links[if_id] == LINKTYPE_RTAC_SERIAL and len(payload) > RTAC_HEADER
                    and payload[8] in DATA_EVENTS):
                t = (high << 32) | low
                late = any(c.startswith(READ_LATE) for c in
                           _comments(block, order, 28 + (captured + 3) // 4 * 4, len(block) - 4))
                if reads and reads[-1][0] == t:
                    reads[-1] = (t, reads[-1][1] + payload[RTAC_HEADER:], reads[-1][2] or late)
                else:
                    reads.append((t, payload[RTAC_HEADER:], late))
    return reads
