#pragma once
// Exact decimal renderings of nanosecond times (no floating-point rounding).
#include <fmt/format.h>

#include "core/time.hpp"

namespace rtu {

// "12.345678901" with `decimals` (0-9) digits after the point, truncated toward -inf.
void append_seconds(fmt::memory_buffer& out, Nanos t, int decimals = 9);
// Milliseconds with three decimals: "12.345".
void append_millis(fmt::memory_buffer& out, Nanos t);

}  // namespace rtu
