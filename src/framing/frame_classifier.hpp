#pragma once
// Checks that depend only on a frame's own bytes: the CRC verdict, which length rules the
// frame fits (request / response shape), truncation. Shared by the framer and by frames
// imported with known boundaries.
#include "framing/record.hpp"

namespace rtu {

// Sets crc_ok, shape_fit and the kCrc / kTruncated issues of a frame record.
// `crc_known_valid`: the caller has just found the CRC zero over exactly these bytes (the
// framer's CRC-confirmed lengths), so it is not computed a second time.
void classify_frame(Record& frame, bool crc_known_valid = false);

}  // namespace rtu
