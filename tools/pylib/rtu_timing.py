"""Modbus RTU's silences, t1.5 and t3.5, for the Python tools and tests, written once.

MODBUS over Serial Line V1.02, §2.5.1.1: a frame's characters follow each other with less
than 1.5 character times of silence (t1.5), and frames are separated by at least 3.5
(t3.5). Above 19200 baud both are fixed, at 750 µs and 1.75 ms, so that a fast line does not
ask a receiver for timer resolution it rarely has. A character is 11 bits on a Modbus line
(start, 8 data, parity or a second stop, stop); a capture that says otherwise passes its own.

Written independently of the C++ one (src/serial/line_settings.cpp), so that a check of rtuscope's
timing flags does not reuse rtuscope's rule. Standard library only; scripts find this folder
with one sys.path line relative to their own file.
"""

MODBUS_BITS_PER_CHAR = 11
FIXED_ABOVE_BAUD = 19200
T1_5_FIXED = 750e-6
T3_5_FIXED = 1750e-6


def char_seconds(baud, bits=MODBUS_BITS_PER_CHAR):
    """One character's time on the wire, in seconds."""
    return bits / baud


def t1_5_seconds(baud, bits=MODBUS_BITS_PER_CHAR):
    """The longest silence allowed inside a frame, in seconds."""
    return T1_5_FIXED if baud > FIXED_ABOVE_BAUD else 1.5 * char_seconds(baud, bits)


def t3_5_seconds(baud, bits=MODBUS_BITS_PER_CHAR):
    """The shortest silence allowed between frames, in seconds."""
    return T3_5_FIXED if baud > FIXED_ABOVE_BAUD else 3.5 * char_seconds(baud, bits)
