#pragma once
// Serial line settings and the Modbus timing derived from them
// (MODBUS over Serial Line V1.02 §2.5.1.1).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "core/time.hpp"

namespace rtu {

enum class Parity : std::uint8_t { kNone, kEven, kOdd };

struct LineSettings {
  std::uint32_t baud = 9600;
  Parity parity = Parity::kEven;
  std::uint8_t stop_bits = 1;

  // Bits on the wire per character: start + 8 data + parity + stop. The spec's "11 bits"
  // holds for 8E1 and 8N2; a non-conforming 8N1 line really carries 10, and the timing
  // maths uses what is really on the wire.
  [[nodiscard]] std::uint32_t bits_per_char() const;
  [[nodiscard]] Nanos char_time() const;
  // Inter-character timeout and inter-frame delay. The spec fixes them at 750 µs and
  // 1750 µs above 19200 baud, where computed values would be too short for UART drivers.
  [[nodiscard]] Nanos t1_5() const;
  [[nodiscard]] Nanos t3_5() const;
  // "9600 8E1"
  [[nodiscard]] std::string describe() const;

  bool operator==(const LineSettings&) const = default;
};

char parity_letter(Parity p);
std::optional<Parity> parse_parity(std::string_view text);  // N|E|O (any case)
// "19200:8E1", "9600:8N2" (8 data bits only); nullopt when malformed.
std::optional<LineSettings> parse_line_spec(std::string_view text);

}  // namespace rtu
