#pragma once
// Exact decimal renderings of nanosecond times (no floating-point rounding).
#include <fmt/format.h>

#include "core/time.hpp"

namespace rtu {

// "12.345678901" with `decimals` (0-9) digits after the point, truncated toward -inf.
void append_seconds(fmt::memory_buffer& out, Nanos t, int decimals = 9);
// Milliseconds with three decimals: "12.345".
void append_millis(fmt::memory_buffer& out, Nanos t);

// Times from this instant on (2001-09-09) are wall-clock times (a live capture, a pcap
// file); smaller ones are seconds from the start of a capture.
constexpr Nanos kWallClockFrom = 1'000'000'000 * kNanosPerSecond;
// Whole days since 1970-01-01 (UTC) of a wall-clock time.
[[nodiscard]] constexpr Nanos utc_day(Nanos t) {
  constexpr Nanos kDay = 86'400 * kNanosPerSecond;
  return t >= 0 ? t / kDay : (t - kDay + 1) / kDay;
}
// "2026-11-23" (UTC) for a wall-clock time.
void append_utc_date(fmt::memory_buffer& out, Nanos t);
// "08:43:45.420647" (UTC time of day) with `decimals` (0-9) digits after the point.
void append_utc_time_of_day(fmt::memory_buffer& out, Nanos t, int decimals = 6);

}  // namespace rtu
