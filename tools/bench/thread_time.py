#!/usr/bin/env python3
"""Where a run's time goes, thread by thread: runs COMMAND, reads each of its threads' CPU
time (nanoseconds, /proc/PID/task/TID/schedstat) every PERIOD milliseconds, and prints the
wall time, each thread's CPU time and share of the wall time by its name (rtuscope names its
stages' threads: rtu-read, rtu-framing; the main thread pairs, decodes and writes), and the
share of the usable cores that stayed idle.

  thread_time.py [--period MS] [--timeline] -- COMMAND [ARGS...]

--timeline also prints every period's shares, to see how the stages take turns.

A thread's time is known up to its last reading: one that ends between two readings loses
up to a period's time, so keep the period short against the run (default 20 ms).
"""
import argparse
import os
import subprocess
import sys
import time


def thread_times(pid):
    """{tid: (name, cpu ns)} of the process's threads now; those that ended are left out."""
    times = {}
    try:
        tids = os.listdir(f"/proc/{pid}/task")
    except FileNotFoundError:
        return times
    for tid in tids:
        try:
            with open(f"/proc/{pid}/task/{tid}/comm") as comm:
                name = comm.read().strip()
            with open(f"/proc/{pid}/task/{tid}/schedstat") as stat:
                ns = int(stat.read().split()[0])
        except (FileNotFoundError, ProcessLookupError):
            continue
        times[tid] = (name, ns)
    return times


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--period", type=float, default=20.0, help="milliseconds")
    parser.add_argument("--timeline", action="store_true")
    parser.add_argument("command", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        parser.error("a COMMAND to run is needed")

    cores = len(os.sched_getaffinity(0))
    start = time.monotonic()
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL)
    last = {}  # tid: (name, ns) at its latest reading
    order = []
    previous_t, previous = start, {}
    while child.poll() is None:
        now = thread_times(child.pid)
        t = time.monotonic()
        for tid, value in now.items():
            if tid not in order:
                order.append(tid)
            last[tid] = value
        if args.timeline and t > previous_t:
            shares = [
                100.0 * (now[tid][1] - previous.get(tid, (None, 0))[1]) / ((t - previous_t) * 1e9)
                if tid in now else 0.0
                for tid in order
            ]
            print(f"{t - start:7.3f} s  " + " ".join(f"{s:4.0f}" for s in shares)
                  + f"  sum {sum(shares):4.0f}%")
        previous_t, previous = t, now
        time.sleep(args.period / 1000.0)
    wall = time.monotonic() - start
    if child.returncode != 0:
        print(f"thread_time.py: the command exited with {child.returncode}", file=sys.stderr)

    print(f"wall {wall:.3f} s on {cores} usable cores")
    total = 0
    for tid in order:
        name, ns = last[tid]
        total += ns
        print(f"  {name:<16} {ns / 1e9:7.3f} s CPU  {100.0 * ns / 1e9 / wall:5.1f}% of the wall time")
    idle = max(0.0, 1.0 - total / 1e9 / (wall * cores))
    print(f"  all threads      {total / 1e9:7.3f} s CPU; the cores idle {100.0 * idle:.1f}% of the run")
    return child.returncode


if __name__ == "__main__":
    sys.exit(main())
