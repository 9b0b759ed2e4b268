"""Runs tshark and returns one dict of field values per packet (shared by the tshark tests)."""
import os
import subprocess

# Preferences every check uses: CRC verified, and the port convention of rtuscope's exports
# (requests 1 -> 502, responses 502 -> 1) so every function code is classified.
MODBUS_PREFS = ["-o", "mbrtu.crc_verification:TRUE", "-o", "mbrtu.tcp.port:502"]


def run_fields(tshark, path, fields, extra=()):
    """Returns [{field: [values...]}...], one dict per frame. Several values of a field are
    joined by tshark with an ASCII record separator, which comments never hold."""
    cmd = [tshark, "-n", "-r", path, *MODBUS_PREFS, *extra, "-T", "fields",
           "-E", "separator=\t", "-E", "occurrence=a", "-E", "aggregator=\x1e", "-E", "quote=n"]
    for f in fields:
        cmd += ["-e", f]
    env = dict(os.environ)
    # An empty private configuration: the user's Wireshark profile must not change results.
    env["WIRESHARK_CONFIG_DIR"] = os.path.join(os.path.dirname(os.path.abspath(path)),
                                               ".wireshark-empty")
    os.makedirs(env["WIRESHARK_CONFIG_DIR"], exist_ok=True)
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    if proc.returncode != 0:
        raise AssertionError(f"tshark failed ({proc.returncode}) on {path}: {proc.stderr}")
    rows = []
    for line in proc.stdout.split("\n"):
        if not line:
            continue
        cols = line.split("\t")
        cols += [""] * (len(fields) - len(cols))
        rows.append({f: ([] if c == "" else c.split("\x1e")) for f, c in zip(fields, cols)})
    return rows


def one(row, field):
    """The single value of a field, or None when absent."""
    values = row[field]
    if not values:
        return None
    if len(values) != 1:
        raise AssertionError(f"{field} has several values: {values}")
    return values[0]
