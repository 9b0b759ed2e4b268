#!/usr/bin/env python3
"""Writes the seed corpora of the file-reading fuzz targets, cut from the bundled inputs.

Each seed is the start of a real input, a few KB at most: text hex captures and Saleae
exports from captures/, device maps from dissectors/ (the [device], [var] and [exceptions]
tables, each space with its first points and every point that learns a var), bus files
from captures/ and the bus-file examples of dissectors/README.md. With the path of a built
`rtuscope`, also pcap and pcapng seeds: short text captures exported as frames (LINKTYPE
252) and, with --raw, as raw reads and frames (250 and 252).

Files named seed-* are rewritten by this script; files named crash-* or regression-* are
findings and are never touched.

usage: tests/fuzz/make_file_seeds.py [RTUSCOPE_BINARY]   (run from the top of the source tree)
"""
import pathlib
import subprocess
import sys
import tempfile

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
    for name in ["device_examples", "bus_9600_usb", "bus_19200_faults_usb", "sim_yakotec",
                 "wrong_baud_19200_as_9600"]:
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


def pcap_seeds(rtuscope: str) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        for name, lines in [("device_examples", 40), ("bus_19200_faults_usb", 12)]:
            cut = pathlib.Path(tmp) / f"{name}.hex"
            cut.write_text("".join((ROOT / f"captures/{name}.hex").read_text()
                                   .splitlines(keepends=True)[:lines]))
            for suffix, extra in [("pcapng", []), ("pcap", []), ("raw.pcapng", ["--raw"])]:
                out = pathlib.Path(tmp) / f"{name}.{suffix}"
                subprocess.run([rtuscope, "export", str(cut), "-o", str(out), *extra],
                               check=True, stdout=subprocess.DEVNULL)
                write("pcap", f"{name}.{suffix}", out.read_bytes())


if __name__ == "__main__":
    text_seeds()
    if len(sys.argv) > 1:
        pcap_seeds(sys.argv[1])
