#include "report/timing_note.hpp"

#include <fmt/format.h>

namespace rtu {

std::string timing_note(const CaptureInfo& info) {
  if (!info.has_bytes) return "no bytes in the capture: no timing was observed";
  // Outputs written before decoding ended know only the starting resolution.
  const Nanos resolution = info.resolution_at_end();
  const double res_ms = static_cast<double>(resolution) / 1e6;
  const Nanos t15 = info.line.t1_5();
  const Nanos t35 = info.line.t3_5();
  if (resolution < t15) {
    return fmt::format("gaps down to {:.3f} ms are observable: t1.5 and t3.5 are checked", res_ms);
  }
  if (resolution < t35) {
    return fmt::format(
        "gaps below {:.3f} ms are not observable in this capture: t3.5 is checked only where "
        "a gap exceeds it by that margin, t1.5 is not checked",
        res_ms);
  }
  return fmt::format(
      "gaps below {:.1f} ms are not observable in this capture (batched reads): frames are "
      "found by length and CRC, t1.5/t3.5 are not checked",
      res_ms);
}

std::string resolution_text(const CaptureInfo& info) {
  const std::string at_end = fmt::format("{:.3f} ms", to_millis(info.resolution_at_end()));
  if (info.learned_resolution == kUnknownTime) return at_end;
  return fmt::format("{} (learned from the reads: decoding started from {:.3f} ms)", at_end,
                     to_millis(info.timing_resolution));
}

}  // namespace rtu
