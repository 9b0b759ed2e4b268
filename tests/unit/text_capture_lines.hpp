#pragma once
// Lines of rtuscope's text hex capture format for tests that write captures by hand:
// "<seconds with nine decimals> <hex bytes>", integer nanoseconds printed exactly.
#include <fmt/format.h>

#include <cstdint>
#include <span>
#include <string>

#include "core/time.hpp"

namespace rtu::test {

// 1700000000.010000000 (no sign: the tests' times are positive).
inline std::string decimal_seconds(Nanos t) {
  return fmt::format("{}.{:09}", t / kNanosPerSecond, t % kNanosPerSecond);
}

// One read: its end time, then its bytes.
inline std::string text_hex_line(Nanos t_end, std::span<const std::uint8_t> bytes) {
  std::string line = decimal_seconds(t_end);
  for (const std::uint8_t byte : bytes) line += fmt::format(" {:02x}", byte);
  line += '\n';
  return line;
}

}  // namespace rtu::test
