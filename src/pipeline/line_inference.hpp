#pragma once
// Line settings a capture does not declare, inferred from what its timing shows.
//
// Back-to-back bytes start one character time apart, so where each byte has its own
// timestamp (per-byte reads, logic analyser exports) the spacing most bytes share is the
// character time. It fits one standard rate at one character size (LineCheck::infer_line).
// The size cannot tell 8E1, 8O1 and 8N2 apart (all 11 bits: after the UART the parity bit
// is gone), so the Modbus rule decides: even parity, unless 2 stop bits without parity.
// The settings are then tried on a sample of the capture: the share of frames whose CRC
// holds says how sure the inference is.
//
// Where reads are batched (USB adapters), the spacing is not observable and nothing is
// inferred: the settings stay assumed, and the user is told why.
#include <cstdint>
#include <functional>
#include <optional>

#include "framing/capture_info.hpp"
#include "framing/line_check.hpp"
#include "pipeline/decode_pipeline.hpp"

namespace rtu {

// Frames a sample of the capture holds when decoded with some settings.
struct FrameSample {
  std::uint64_t reads = 0;   // reads of the capture the sample covers
  std::uint64_t frames = 0;  // frames found
  std::uint64_t crc_ok = 0;  // of which have a valid CRC
};
using FrameSampler = std::function<FrameSample(const LineSettings& line)>;

// Whether settings are inferred: asked for (--baud auto), or nothing gave a baud rate.
[[nodiscard]] bool wants_inference(const LineOverrides& overrides, bool declared);

// Sets info.line from the timing `check` measured when it can, keeping what the user gave
// (parity or stop bits fix the character size), and says what was inferred and how sure
// it is in info.warnings. Returns whether the settings were inferred.
bool infer_line_settings(CaptureInfo& info, const LineCheck& check, Nanos precision,
                         const LineOverrides& overrides, const FrameSampler& sample);

}  // namespace rtu
