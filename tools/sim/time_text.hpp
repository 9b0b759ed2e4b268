#pragma once
// Exact decimal seconds for the simulator's outputs: integer nanoseconds printed with nine
// decimals, so every file states the same instants to the nanosecond (no floating point).
#include <fmt/format.h>

#include <string>

#include "core/time.hpp"

namespace rtu::sim {

inline std::string seconds_text(Nanos t) {
  const char* sign = t < 0 ? "-" : "";
  const Nanos a = t < 0 ? -t : t;
  return fmt::format("{}{}.{:09}", sign, a / kNanosPerSecond, a % kNanosPerSecond);
}

}  // namespace rtu::sim
