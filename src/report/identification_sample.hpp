#pragma once
// What the models a report calls identified rest on: how much of the capture identification
// looked at, and why its look ended. The report says so, because a look cut short by its
// memory bound (a capture of long frames) rests on fewer frames than were asked for.
#include <cstdint>
#include <string>
#include <string_view>

namespace rtu {

enum class SampleEnd : std::uint8_t {
  kEnough,      // it looked at as many frames as were asked for
  kCaptureEnd,  // the capture ended (or broke) first: it looked at all there was
  kHeldBound,   // the records held for the decoding meanwhile reached their bound
};

// Stable names (JSON): "enough", "capture_end", "held_bound".
constexpr std::string_view sample_end_name(SampleEnd end) {
  switch (end) {
    case SampleEnd::kEnough: return "enough";
    case SampleEnd::kCaptureEnd: return "capture_end";
    case SampleEnd::kHeldBound: return "held_bound";
  }
  return "capture_end";
}

struct IdentificationSample {
  std::uint64_t frames_wanted = 0;  // --identify-frames; 0 for the whole capture
  std::uint64_t frames = 0;         // frames it looked at
  std::uint64_t noise_bytes = 0;    // bytes of noise it looked at (each weighs as a frame)
  SampleEnd end = SampleEnd::kCaptureEnd;
  std::uint64_t held_bound_bytes = 0;  // the bound meant by SampleEnd::kHeldBound
};

// One sentence for the text and HTML reports: what identification looked at, and what
// to do when its sample was cut short.
std::string describe(const IdentificationSample& sample);

}  // namespace rtu
