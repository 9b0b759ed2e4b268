#!/usr/bin/env python3
"""Runs the built rtuscope on a rotation set and checks that it is read as one capture.

The set is made from a sample capture: `rtuscope export --raw` writes its reads to pcapng,
which is split here into site-0001.pcapng ... site-0004.pcapng the way `rtuscope live
--rotate` cuts a recording (each file with its own header and interface, cut only between
reads), keeping only the raw reads, as a live recording holds. The whole recording is
written the same way as one file. Then:
  * `decode` of the quoted glob 'site-*.pcapng' and of the paths in a shuffled order give
    exactly the records of the whole file (JSONL and text, all but the header's source);
  * `report --format json` and `export` give the same as for the whole file;
  * without site-0002.pcapng, a warning on stderr and in the header names the gap;
  * a file that overlaps another in time is an error (status 2) naming both.
"""
import json
import os
import random
import struct
import subprocess
import sys
import tempfile

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail  # noqa: E402  (after the path line)
from pcapng_reads import EPB, IDB, LINKTYPE_RTAC_SERIAL, SHB, blocks  # noqa: E402

PARTS = 4


def run(cmd, expect=0):
    result = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if result.returncode != expect:
        fail(f"{' '.join(cmd)} exited {result.returncode} (expected {expect}): {result.stderr}")
    return result


def raw_reads_only(data):
    """The section header, the raw-read interface (as interface 0) and its packets."""
    header, interface, packets = None, None, []
    interfaces = []
    for kind, block, order in blocks(data):
        if kind == SHB:
            header = block
        elif kind == IDB:
            link_type = struct.unpack_from(order + "H", block, 8)[0]
            interfaces.append(link_type)
            if link_type == LINKTYPE_RTAC_SERIAL:
                interface = block
        elif kind == EPB:
            if_id, high, low = struct.unpack_from(order + "III", block, 8)
            if interfaces[if_id] == LINKTYPE_RTAC_SERIAL:
                block = block[:8] + struct.pack(order + "I", 0) + block[12:]
                packets.append(((high << 32) | low, block))
    if header is None or interface is None:
        fail("the export holds no raw-read interface")
    return header, interface, packets


def write_pcapng(path, header, interface, packets):
    with open(path, "wb") as out:
        out.write(header + interface + b"".join(block for _, block in packets))


def split(packets, parts):
    """`parts` runs of packets, cut only where the time changes (between two reads)."""
    cuts = [0]
    for i in range(1, parts):
        at = len(packets) * i // parts
        while at < len(packets) and packets[at][0] == packets[at - 1][0]:
            at += 1
        cuts.append(at)
    cuts.append(len(packets))
    return [packets[a:b] for a, b in zip(cuts, cuts[1:])]


def without_source(jsonl):
    lines = [json.loads(line) for line in jsonl.splitlines() if line.strip()]
    if not lines or lines[0].get("kind") != "capture":
        fail("decode output does not start with the capture header")
    source = lines[0].pop("source")
    return source, lines


def text_without_source(text):
    """All but the first line, which names the source."""
    return text.splitlines()[1:]


def main():
    rtuscope, capture = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory(prefix="rtuscope-set-") as tmp:
        exported = os.path.join(tmp, "exported.pcapng")
        run([rtuscope, "export", capture, "-o", exported, "--raw"])
        with open(exported, "rb") as f:
            header, interface, packets = raw_reads_only(f.read())
        whole = os.path.join(tmp, "whole.pcapng")
        write_pcapng(whole, header, interface, packets)
        sets = os.path.join(tmp, "rotated")
        os.mkdir(sets)
        parts = []
        for i, run_of_packets in enumerate(split(packets, PARTS)):
            part = os.path.join(sets, f"site-{i + 1:04}.pcapng")
            write_pcapng(part, header, interface, run_of_packets)
            parts.append(part)
        pattern = os.path.join(sets, "site-*.pcapng")

        # decode: glob and explicit paths in any order read as the whole file.
        source, whole_records = without_source(
            run([rtuscope, "decode", whole, "--format", "jsonl"]).stdout)
        glob_run = run([rtuscope, "decode", pattern, "--format", "jsonl"])
        set_source, set_records = without_source(glob_run.stdout)
        if set_records != whole_records:
            fail("decode of the glob differs from decode of the whole file")
        if len(whole_records) < 100:
            fail(f"only {len(whole_records)} records: the sample is too small to test anything")
        expected_source = f"{parts[0]} \u2026 {parts[-1]} ({PARTS} files)"
        if set_source != expected_source:
            fail(f"source is {set_source!r}, expected {expected_source!r}")
        if glob_run.stderr:
            fail(f"a complete set must read without warnings: {glob_run.stderr}")
        shuffled = parts[:]
        random.Random(7).shuffle(shuffled)
        if shuffled == parts:
            shuffled.reverse()
        _, shuffled_records = without_source(
            run([rtuscope, "decode", *shuffled, "--format", "jsonl"]).stdout)
        if shuffled_records != whole_records:
            fail("decode of the paths in a shuffled order differs from the whole file")
        whole_text = run([rtuscope, "decode", whole]).stdout
        set_text = run([rtuscope, "decode", *shuffled]).stdout
        if text_without_source(set_text) != text_without_source(whole_text):
            fail("text decode of the set differs from the whole file")

        # report: the same statistics, timing and findings.
        whole_report = json.loads(run([rtuscope, "report", whole, "--format", "json"]).stdout)
        set_report = json.loads(run([rtuscope, "report", pattern, "--format", "json"]).stdout)
        whole_report["capture"].pop("source")
        set_report["capture"].pop("source")
        if set_report != whole_report:
            fail("report of the set differs from the report of the whole file")

        # export: the same frames.
        exports = []
        for name, args in (("whole-export.pcapng", [whole]), ("set-export.pcapng", shuffled)):
            out = os.path.join(tmp, name)
            counts = run([rtuscope, "export", *args, "-o", out]).stderr.split(":")[-1]
            _, records = without_source(run([rtuscope, "decode", out, "--format", "jsonl"]).stdout)
            exports.append((counts, records))
        if exports[0] != exports[1]:
            fail(f"export of the set differs from the whole file: {exports[0][0]} / {exports[1][0]}")

        # A missing middle file: a warning on stderr, and in the header.
        gap = run([rtuscope, "decode", parts[0], parts[2], parts[3], "--format", "jsonl"])
        message = (f"{parts[2]}: a file seems to be missing before it (after {parts[0]}): "
                   f"the rotation numbering skips {parts[1]}")
        if f"rtuscope: warning: {message}" not in gap.stderr:
            fail(f"no warning about the missing file on stderr: {gap.stderr!r}")
        header_warnings = json.loads(gap.stdout.splitlines()[0])["warnings"]
        if not any(message in w for w in header_warnings):
            fail(f"no warning about the missing file in the header: {header_warnings}")

        # Overlapping files: an error naming both.
        overlap = run([rtuscope, "decode", whole, parts[1]], expect=2)
        if parts[1] not in overlap.stderr or whole not in overlap.stderr \
                or "overlap in time" not in overlap.stderr:
            fail(f"the overlap error does not name both files: {overlap.stderr!r}")
    print(f"ok: {len(whole_records)} records, {PARTS} files read as one capture")


if __name__ == "__main__":
    main()
