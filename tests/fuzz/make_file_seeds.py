#!/usr/bin/env python3
"""Writes the seed corpora of the file-reading fuzz targets, cut from the bundled inputs.

Each seed is the start of a real input, a few KB at most: text hex captures and Saleae
exports from captures/, device maps from dissectors/ (the [device], [var] and [exceptions]
tables, each space with its first points and every point that learns a var), bus files
from captures/ and the bus-file examples of dissectors/README.md; pcap and pcapng files
holding the first reads and frames of two bundled text captures as raw reads (LINKTYPE 250)
and as frames (252), laid out as rtuscope's export and live recordings write them.

Files named seed-* are rewritten by this script; files named crash-* or regression-* are
findings and are never touched.

usage: tests/fuzz/make_file_seeds.py
"""
import pathlib
import struct

ROOT = pathlib.Path(__file__).resolve().parents[2]
CORPORA = ROOT / "captures/regressions/fuzz"
LIMIT = 3000  # bytes per text seed


def first_lines(path: pathlib.Path, limit: int = LIMIT) -> str:
    """The whole lines of `path` that fit in `limit` bytes."""
    out = ""
    for line in path.read_text().splitlines(keepends=True):
        if len(out) + len(line) > limit:
            break
        out += line
    return out


def write(target: str, name: str, text) -> None:
    directory = CORPORA / target
    directory.mkdir(parents=True, exist_ok=True)
    data = text.encode() if isinstance(text, str) else text
    (directory / f"seed-{name}").write_bytes(data)


def cut_map(path: pathlib.Path, points_per_space: int = 3) -> str:
    """The map without its leading comments, each space cut to its first points."""
    blocks = []  # (header line, lines)
    for line in path.read_text().splitlines(keepends=True):
        if line.startswith("["):
            blocks.append([line])
        elif blocks:
            blocks[-1].append(line)
    out = []
    kept_in_space = 0
    for block in blocks:
        header = block[0]
        if ".point]]" in header:
            learns = any(line.startswith("learn") for line in block)
            if kept_in_space >= points_per_space and not learns:
                continue
            kept_in_space += 1
        elif header.startswith("[space."):
            kept_in_space = 0
        out.extend(block)
    return "".join(out)


def text_seeds() -> None:
    # bus_9600_perbyte: declared settings and one byte a line, read once by `report`.
    for name in ["device_examples", "bus_9600_usb", "bus_19200_faults_usb", "sim_yakotec",
                 "wrong_baud_19200_as_9600", "bus_9600_perbyte"]:
        write("text_hex", name + ".hex", first_lines(ROOT / f"captures/{name}.hex", 1500))
    for name in ["device_examples_saleae_legacy", "device_examples_saleae_table",
                 "sigrok_wizmodbus_rxtx", "sigrok_flowmeter_0lpm"]:
        write("saleae_csv", name + ".csv", first_lines(ROOT / f"captures/{name}.csv", 1500))
    for path in sorted((ROOT / "dissectors").glob("*.toml")):
        write("device_map", path.name, cut_map(path))
    for path in sorted((ROOT / "captures").glob("*.bus.toml")):
        write("bus_file", path.name, path.read_text())
    readme = (ROOT / "dissectors/README.md").read_text()
    bus_section = readme[readme.index("## Bus files"):]
    examples = bus_section.split("```toml\n")[1:3]
    for i, example in enumerate(examples):
        write("bus_file", f"readme-example-{i + 1}.toml", example[:example.index("```")])


def hex_reads(name: str, count: int):
    """The first `count` reads of a text hex capture: (time in ns, bytes)."""
    reads = []
    for line in (ROOT / f"captures/{name}.hex").read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        time, *pairs = line.split()
        whole, _, fraction = time.partition(".")
        ns = int(whole) * 10**9 + int((fraction + "000000000")[:9])
        reads.append((ns, bytes.fromhex("".join(pairs))))
        if len(reads) == count:
            break
    return reads


def frames_of(reads, gap_ns: int = 2_000_000):
    """Per-byte reads grouped into frames at silences longer than `gap_ns`: (start, bytes)."""
    frames = []
    last = None
    for t, data in reads:
        if last is None or t - last > gap_ns:
            frames.append([t, b""])
        frames[-1][1] += data
        last = t
    return [(t, data) for t, data in frames]


def upper_pdu(payload: bytes, dissector: bytes = b"mbrtu") -> bytes:
    """A LINKTYPE 252 record: dissector-name TLV (NUL-padded to 4), end TLV, payload."""
    name = dissector + b"\0" * (-len(dissector) % 4 or 4)
    return struct.pack(">HH", 12, len(name)) + name + struct.pack(">HH", 0, 0) + payload


def rtac(t_ns: int, payload: bytes, event: int = 0x02) -> bytes:
    """A LINKTYPE 250 record: seconds, µs, event, control lines, footer, bytes."""
    return struct.pack(">IIBBH", t_ns // 10**9, t_ns % 10**9 // 1000, event, 0, 0) + payload


def classic_pcap(link_type: int, records) -> bytes:
    out = struct.pack("<IHHiIII", 0xA1B2C3D4, 2, 4, 0, 0, 65535, link_type)
    for t, data in records:
        out += struct.pack("<IIII", t // 10**9, t % 10**9 // 1000, len(data), len(data)) + data
    return out


def pcapng_block(kind: int, body: bytes) -> bytes:
    body += b"\0" * (-len(body) % 4)
    return struct.pack("<II", kind, len(body) + 12) + body + struct.pack("<I", len(body) + 12)


def pcapng(interfaces, packets) -> bytes:
    """`interfaces`: (link type, description); `packets`: (interface, time ns, data)."""
    out = pcapng_block(0x0A0D0D0A, struct.pack("<IHHq", 0x1A2B3C4D, 1, 0, -1))
    for link_type, description in interfaces:
        text = description.encode()
        options = struct.pack("<HH", 3, len(text)) + text + b"\0" * (-len(text) % 4)
        options += struct.pack("<HHB3x", 9, 1, 9) + struct.pack("<HH", 0, 0)  # if_tsresol ns
        out += pcapng_block(1, struct.pack("<HHI", link_type, 0, 0) + options)
    for interface, t, data in packets:
        body = struct.pack("<IIIII", interface, t >> 32, t & 0xFFFFFFFF, len(data), len(data))
        out += pcapng_block(6, body + data)
    return out


def pcap_seeds() -> None:
    """Both link types rtuscope reads, in the layouts `export`, `export --raw` and `live -w`
    write them, from the first exchanges of two bundled captures."""
    per_byte = hex_reads("device_examples", 48)
    frames = frames_of(per_byte)
    usb = hex_reads("bus_19200_faults_usb", 10)
    write("pcap", "frames-252.pcap", classic_pcap(252, [(t, upper_pdu(f)) for t, f in frames]))
    noise = [(frames[0][0] - 5_000_000, upper_pdu(b"\xff\x00", b"data"))]
    write("pcap", "frames-and-noise-252.pcapng",
          pcapng([(252, "RS-485 9600 8E1; timing resolution 0.001 ms")],
                 [(0, t, f) for t, f in noise + [(t, upper_pdu(f)) for t, f in frames]]))
    reads = [(0, t, rtac(t, data)) for t, data in usb]
    reads.insert(3, (0, usb[3][0], rtac(usb[3][0], b"", 0x08)))  # a parity error event
    end = usb[-1][0] + 50_000_000
    write("pcap", "reads-250-live.pcapng",
          pcapng([(250, "RS-485 19200 8E1; response timeout 300 ms")],
                 reads + [(0, end, rtac(end, b"", 0x06))]))
    # Declared line settings and resolution, as `export --raw` writes them: report and export
    # read such a file once (declared_survey); a section that declares a response timeout
    # later makes them decode it again.
    declared = pcapng([(250, "RS-485 19200 8E1; timing resolution 16 ms")], reads)
    write("pcap", "reads-250-declared.pcapng", declared)
    later = [(0, t + 10**9, rtac(t + 10**9, data)) for t, data in usb]
    write("pcap", "reads-250-timeout-declared-later.pcapng",
          declared + pcapng([(250, "RS-485 19200 8E1; response timeout 300 ms")], later))
    write("pcap", "reads-250-and-frames-252.pcapng",
          pcapng([(252, "RS-485 9600 8E1"), (250, "RS-485 9600 8E1")],
                 [(0, t, upper_pdu(f)) for t, f in frames[:4]] +
                 [(1, t, rtac(t, data)) for t, data in per_byte[:24]]))


if __name__ == "__main__":
    text_seeds()
    pcap_seeds()
