"""What a running process uses, read from Linux's /proc, for the soak and benchmark tools.

  cpu_seconds(pid) -> float  user + system CPU time so far (utime + stime of /proc/PID/stat)
  cpu_seconds_exact(pid) -> float
                             the same to the nanosecond, from the scheduler's own count
                             (/proc/PID/task/*/schedstat) of the threads alive now
  rss_kb(pid) -> int         resident memory now (VmRSS of /proc/PID/status)
  open_files(pid) -> int     open file descriptors now (entries of /proc/PID/fd)
"""
import os


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        # The command name may hold spaces and parentheses: the fields follow its last ")".
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def cpu_seconds_exact(pid):
    # utime and stime come in clock ticks (10 ms): a process that uses 0.1 s in 20 s reads
    # anywhere from 0.09 to 0.11 s, too coarse to tell 0.4% of a core from 0.6%.
    total = 0
    for task in os.listdir(f"/proc/{pid}/task"):
        try:
            with open(f"/proc/{pid}/task/{task}/schedstat") as f:
                total += int(f.read().split()[0])
        except FileNotFoundError:
            pass  # the thread ended in between
    return total / 1e9


def rss_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))


def open_files(pid):
    return len(os.listdir(f"/proc/{pid}/fd"))
