#include "pipeline/line_inference.hpp"

#include <fmt/format.h>

#include <string>
#include <string_view>

namespace rtu {
namespace {

// Below this share of CRC-valid frames in the sample, the inference is called doubtful.
constexpr std::uint64_t kSurePercent = 90;
constexpr std::uint64_t kSureFrames = 10;

// The settings a character size means when the user gave no parity or stop bits.
void apply_character_size(LineSettings& line, std::uint32_t bits, const LineOverrides& overrides) {
  if (overrides.parity || overrides.stop_bits) return;  // the user's choice fixed the size
  switch (bits) {
    case 10:
      line.parity = Parity::kNone;
      line.stop_bits = 1;
      break;
    case 12:
      line.parity = Parity::kEven;
      line.stop_bits = 2;
      break;
    default:
      line.parity = Parity::kEven;
      line.stop_bits = 1;
      break;
  }
}

// Why the character size gives these settings.
std::string size_text(std::uint32_t bits, const LineOverrides& overrides) {
  if (overrides.parity || overrides.stop_bits) {
    return fmt::format("{} bits a character, as the given parity and stop bits make it", bits);
  }
  switch (bits) {
    case 10: return "10 bits a character: 8N1";
    case 12: return "12 bits a character: 8E2 and 8O2 look alike after the UART, so even parity";
    default:
      return "11 bits a character: 8E1, 8O1 and 8N2 look alike after the UART, so even parity "
             "by the Modbus rule";
  }
}

std::string confidence_text(const FrameSample& sample) {
  if (sample.frames == 0) {
    return fmt::format("no frame in the first {} reads to confirm it: doubtful", sample.reads);
  }
  const bool sure =
      sample.frames >= kSureFrames && sample.crc_ok * 100 >= sample.frames * kSurePercent;
  return fmt::format("{} of {} frames in the first {} reads have a valid CRC: {}", sample.crc_ok,
                     sample.frames, sample.reads,
                     sure ? "confident" : "doubtful, check the settings");
}

}  // namespace

bool wants_inference(const LineOverrides& overrides, bool declared) {
  return overrides.infer_baud || (!declared && !overrides.baud);
}

bool infer_line_settings(CaptureInfo& info, const LineCheck& check, Nanos precision,
                         const LineOverrides& overrides, const FrameSampler& sample) {
  std::optional<std::uint32_t> fixed_size;
  if (overrides.parity || overrides.stop_bits) fixed_size = info.line.bits_per_char();
  const auto inferred = check.infer_line(precision, fixed_size);
  if (!inferred) {
    if (overrides.infer_baud) {
      info.warnings.push_back(fmt::format(
          "--baud auto: the character time cannot be measured (reads are batched, or too few "
          "bytes have their own timestamp); decoding at {}. Frames are still found by length "
          "and CRC; only timings depend on the baud rate",
          info.line.describe()));
    }
    return false;
  }
  info.line.baud = inferred->baud;
  apply_character_size(info.line, inferred->bits_per_char, overrides);
  const FrameSample confirmation = sample(info.line);
  info.warnings.push_back(fmt::format(
      "line settings inferred from the byte timing: {} (back-to-back bytes {:.3f} ms apart in "
      "{} of {} spacings: {} baud at {}); {}; use --baud/--parity/--stop to decode otherwise",
      info.line.describe(), static_cast<double>(inferred->spacing) / 1e6, inferred->agreeing,
      inferred->spacings, inferred->baud, size_text(inferred->bits_per_char, overrides),
      confidence_text(confirmation)));
  return true;
}

}  // namespace rtu
