"""What a running process uses, read from Linux's /proc, for the soak and benchmark tools.

  cpu_seconds(pid) -> float  user + system CPU time so far (utime + stime of /proc/PID/stat)
  rss_kb(pid) -> int         resident memory now (VmRSS of /proc/PID/status)
  open_files(pid) -> int     open file descriptors now (entries of /proc/PID/fd)
"""
import os


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        # The command name may hold spaces and parentheses: the fields follow its last ")".
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def rss_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))


def open_files(pid):
    return len(os.listdir(f"/proc/{pid}/fd"))
