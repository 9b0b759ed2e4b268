#pragma once
// Ground truth as JSON lines, in wire order. The first line describes the capture:
//   {"kind":"capture","generator":"rtusim …","baud":9600,"parity":"E","stop":1,
//    "bits_per_char":11,"records":N,"bytes":M}
// then one line per record:
//   {"kind":"frame","t":…,"t_end":…,"hex":"0103…","slave":1,"fc":3,"role":"request",
//    "txn":7,"device":"yw2050","faults":["crc"]}
//   {"kind":"noise","t":…,"t_end":…,"hex":"ff","cause":"turnaround"}
// - t is the start of the first byte's start bit and t_end the end of the last byte's stop
//   bit, in seconds with 9 decimals, on the same clock as the capture.
// - hex is every byte of the record as it went on the wire (lowercase); concatenating the
//   records' hex gives the capture's byte stream exactly, so every byte of the capture is in
//   exactly one record.
// - slave and fc are the first two bytes as sent (fc includes the exception bit; null when
//   the frame is too short to have one).
// - txn is shared by a request and the response to it (also when the response is damaged or
//   comes from the wrong slave); a request without an answer (timeout, broadcast) has its
//   own txn that no response shares.
// - faults lists what was injected, by issue-catalogue key where one exists: crc, t1.5,
//   t3.5, timeout, truncated, wrong_slave; and also exception (a refused request's answer)
//   and broadcast. A truncated frame is a frame record holding exactly the bytes that got
//   onto the wire (1 to size-1 bytes of the intended frame, CRC thus missing) with the
//   fault "truncated"; t1.5 and t3.5 are set from the wire timing, whatever caused them.
// - heavy profile only: "flipped" lists the indices of the bytes a bit flip changed (fault
//   crc; any byte, address and function code included) and "intended_size" the size a
//   truncated frame was meant to have; noise has the cause "burst", "turnaround" or
//   "glitch" (a lone byte 50-150 us after a frame).
#include <ostream>
#include <span>
#include <string_view>

#include "timeline.hpp"

namespace rtu::sim {

void write_truth(std::ostream& out, const LineSettings& line, std::string_view command,
                 const Timeline& timeline);

}  // namespace rtu::sim
