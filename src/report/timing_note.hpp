#pragma once
#include <string>

#include "framing/capture_info.hpp"

namespace rtu {

// One sentence on what the capture's timestamps can show, for output headers, e.g.
// "gaps below 16.0 ms are not observable in this capture: t1.5/t3.5 not checked".
std::string timing_note(const CaptureInfo& info);

}  // namespace rtu
