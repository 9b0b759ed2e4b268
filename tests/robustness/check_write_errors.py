#!/usr/bin/env python3
"""Outputs that cannot be written: a full disk under the recording, /dev/full as the output,
a pipe whose reader goes away. Nothing already captured may be lost, and the run must say so.

- Recording onto a full disk (a tiny tmpfs when this user may mount one, and a file-size
  limit, which fails writes the same way, everywhere): the run goes on decoding and exits 0;
  it says the recording stopped; the file is valid up to its last whole block (rtuscope and
  tshark read it) and decodes as the live run did up to there. With --stop-on-write-error the
  run stops with exit status 1.
- Frames written to /dev/full, by `demo`, `decode` and `report`: exit 1 with "write failed".
- `demo -w FILE | head -c 300`: the run ends (exit 1, "Broken pipe") and the recording is
  complete, with its end record.
"""
import argparse
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import tempfile

# tools/pylib (check_support), found from this file: any working directory, no install.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "../../tools/pylib"))
from check_support import fail, fresh_dir  # noqa: E402  (after the path line)


def run(cmd, **kwargs):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120, **kwargs)


def limit_file_size(limit):
    def apply():
        # The kernel then fails a write past `limit` with EFBIG, as a full disk does with
        # ENOSPC, after writing what fits; SIGXFSZ would kill the process instead.
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return apply


def mount_tiny_tmpfs(path):
    os.makedirs(path, exist_ok=True)
    if shutil.which("mount") is None or os.geteuid() != 0:
        return False
    return subprocess.run(["mount", "-t", "tmpfs", "-o", "size=8k", "tmpfs", path],
                          capture_output=True).returncode == 0


def framing(line):
    """What a record says about the line (the demo also names its devices: decode does not)."""
    record = json.loads(line)
    return {k: record.get(k) for k in ("kind", "t", "t_end", "gap_ms", "hex", "role", "txn",
                                       "latency_ms")}


def decoded_lines(args, path):
    out = run([args.rtuscope, "decode", "--format", "jsonl", path])
    if out.returncode != 0:
        fail(f"{path} does not decode: {out.stderr}")
    return out.stdout.splitlines()


def check_recording_kept(args, what, path, live_lines, stderr):
    if "recording stopped" not in stderr or "decoding goes on" not in stderr:
        fail(f"{what}: the run did not say the recording stopped:\n{stderr}")
    size = os.path.getsize(path)
    recorded = decoded_lines(args, path)
    tshark = run([args.tshark, "-r", path])
    if tshark.returncode != 0:
        fail(f"{what}: tshark cannot read the cut recording: {tshark.stderr}")
    # The header line names the source; records compare one by one, as far as framing and
    # pairing go. The last records before
    # the cut may be decided differently: the file lacks the end record the live run had.
    live_records = [framing(line) for line in live_lines[1:]]
    kept = [framing(line) for line in recorded[1:]]
    if not 0 < len(kept) < len(live_records):
        fail(f"{what}: {len(kept)} records kept of {len(live_records)} decoded live")
    if kept[:-2] != live_records[:len(kept) - 2]:
        fail(f"{what}: the kept recording does not decode as the live run did")
    print(f"{what}: recording stopped at {size} bytes; {len(kept)} of {len(live_records)} "
          f"records kept and decoded as live; the run decoded all")


def check_full_disk(args, work):
    demo = [args.rtuscope, "demo", "--format", "jsonl"]
    # A file-size limit: a full disk for this process only.
    path = os.path.join(work, "limited.pcapng")
    out = run(demo + ["-w", path], preexec_fn=limit_file_size(8192))
    if out.returncode != 0:
        fail(f"full disk (size limit): exit {out.returncode}, expected 0:\n{out.stderr}")
    check_recording_kept(args, "full disk (size limit)", path, out.stdout.splitlines(),
                         out.stderr)

    out = run(demo + ["-w", os.path.join(work, "stop.pcapng"), "--stop-on-write-error"],
              preexec_fn=limit_file_size(4096))
    if out.returncode != 1 or "write failed" not in out.stderr:
        fail(f"--stop-on-write-error: exit {out.returncode}, expected 1:\n{out.stderr}")
    print("--stop-on-write-error: exit 1 with the reason")

    # A real full filesystem, where this user may mount one.
    mount = os.path.join(work, "tiny")
    if not mount_tiny_tmpfs(mount):
        print("tmpfs: cannot mount here; the size limit above stands for it")
        return
    try:
        path = os.path.join(mount, "rec.pcapng")
        out = run(demo + ["-w", path])
        if out.returncode != 0 or "No space left on device" not in out.stderr:
            fail(f"full tmpfs: exit {out.returncode}:\n{out.stderr}")
        check_recording_kept(args, "full tmpfs", path, out.stdout.splitlines(), out.stderr)
    finally:
        subprocess.run(["umount", mount], check=False)


def check_unwritable_output(args, capture):
    for name, cmd in [("demo", [args.rtuscope, "demo", "--format", "jsonl"]),
                      ("decode", [args.rtuscope, "decode", capture]),
                      ("report", [args.rtuscope, "report", capture])]:
        with open("/dev/full", "w") as full:
            out = subprocess.run(cmd, stdout=full, stderr=subprocess.PIPE, text=True, timeout=120)
        if out.returncode != 1 or "standard output: write failed" not in out.stderr:
            fail(f"{name} > /dev/full: exit {out.returncode}, expected 1 and the reason:\n"
                 f"{out.stderr}")
    print("demo, decode, report > /dev/full: exit 1, 'write failed'")


def check_closed_pipe(args, work):
    path = os.path.join(work, "piped.pcapng")
    demo = subprocess.Popen([args.rtuscope, "demo", "--format", "jsonl", "-w", path],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    demo.stdout.read(300)
    demo.stdout.close()  # the reader goes away, as `| head -c 300` does
    _, err = demo.communicate(timeout=60)
    err = err.decode()
    if demo.returncode != 1 or "Broken pipe" not in err:
        fail(f"closed pipe: exit {demo.returncode}, expected 1 and 'Broken pipe':\n{err}")
    tshark = run([args.tshark, "-r", path, "-T", "fields", "-e", "rtacser.eventtype"])
    events = tshark.stdout.split()
    if tshark.returncode != 0 or not events or int(events[-1], 0) != 6:
        fail(f"closed pipe: the recording does not end with CAPTURE_COMPLETE (6): {events[-3:]}")
    decoded_lines(args, path)
    print(f"closed pipe: exit 1; the recording is complete ({len(events)} records)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtuscope", required=True)
    ap.add_argument("--tshark", required=True)
    ap.add_argument("--capture", required=True)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    fresh_dir(args.work)
    work = tempfile.mkdtemp(dir=args.work)
    check_full_disk(args, work)
    check_unwritable_output(args, args.capture)
    check_closed_pipe(args, work)


if __name__ == "__main__":
    main()
