#pragma once
// The warnings about a replay's line settings: which ones were assumed because neither the
// file nor the command line gave them, and whether the byte timing contradicts them. They go
// into CaptureInfo::warnings, so every output's header states them, and on stderr once.
#include <optional>
#include <string>

#include "framing/capture_info.hpp"
#include "framing/line_check.hpp"
#include "pipeline/decode_pipeline.hpp"

namespace rtu {

// The assumed-settings warning, or nullopt when the file or the options gave all three.
// `line` is what the replay decodes with.
std::optional<std::string> assumed_settings_warning(const LineSettings& line, bool declared,
                                                    const LineOverrides& overrides);

// Appends both warnings to info.warnings (info.line is final by then) and, when `print`,
// prints each as "rtuscope: warning: SOURCE: ..." like the readers' warnings.
void add_line_warnings(CaptureInfo& info, bool declared, const LineOverrides& overrides,
                       const LineCheck& check, Nanos precision, bool print);

}  // namespace rtu
