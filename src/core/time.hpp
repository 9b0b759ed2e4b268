#pragma once
// Time in rtuscope is a signed 64-bit count of nanoseconds on the clock of the input
// (any epoch). Integers, not doubles, so replays are bit-exact and sums never drift.
#include <cstdint>
#include <limits>

namespace rtu {

using Nanos = std::int64_t;

inline constexpr Nanos kNanosPerSecond = 1'000'000'000;
inline constexpr Nanos kNanosPerMilli = 1'000'000;
inline constexpr Nanos kNanosPerMicro = 1'000;
// Marks a time that is not known (e.g. a gap that the timestamps cannot show).
inline constexpr Nanos kUnknownTime = std::numeric_limits<Nanos>::min();

constexpr double to_seconds(Nanos t) { return static_cast<double>(t) / 1e9; }
constexpr double to_millis(Nanos t) { return static_cast<double>(t) / 1e6; }

}  // namespace rtu
