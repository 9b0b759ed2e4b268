#pragma once
#include <string>

#include "framing/capture_info.hpp"

namespace rtu {

// One sentence on what the capture's timestamps can show, for output headers, e.g.
// "gaps below 16.0 ms are not observable in this capture: t1.5/t3.5 not checked".
std::string timing_note(const CaptureInfo& info);

// The resolution in milliseconds, and where the reads raised it while decoding, from what, e.g.
// "4.217 ms (learned from the reads: decoding started from 1.000 ms)".
std::string resolution_text(const CaptureInfo& info);

}  // namespace rtu
