#include "serial/line_settings.hpp"

#include <fmt/format.h>

#include <charconv>

namespace rtu {

std::uint32_t LineSettings::bits_per_char() const {
  return 1U + 8U + (parity == Parity::kNone ? 0U : 1U) + stop_bits;
}

Nanos LineSettings::char_time() const {
  return static_cast<Nanos>(bits_per_char()) * kNanosPerSecond / static_cast<Nanos>(baud);
}

// Spec timing is stated in 11-bit characters; over 19200 baud it is a fixed time.
Nanos LineSettings::t1_5() const {
  if (baud > 19200) return 750 * kNanosPerMicro;
  return char_time() * 3 / 2;
}

Nanos LineSettings::t3_5() const {
  if (baud > 19200) return 1750 * kNanosPerMicro;
  return char_time() * 7 / 2;
}

std::string LineSettings::describe() const {
  return fmt::format("{} 8{}{}", baud, parity_letter(parity), stop_bits);
}

char parity_letter(Parity p) {
  switch (p) {
    case Parity::kNone: return 'N';
    case Parity::kEven: return 'E';
    case Parity::kOdd: return 'O';
  }
  return '?';
}

std::optional<Parity> parse_parity(std::string_view text) {
  if (text.size() != 1) return std::nullopt;
  switch (text[0]) {
    case 'N':
    case 'n': return Parity::kNone;
    case 'E':
    case 'e': return Parity::kEven;
    case 'O':
    case 'o': return Parity::kOdd;
    default: return std::nullopt;
  }
}

std::optional<LineSettings> parse_line_spec(std::string_view text) {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos || text.size() != colon + 4 || text[colon + 1] != '8') {
    return std::nullopt;
  }
  LineSettings s;
  const char* first = text.data();
  const auto [end, ec] = std::from_chars(first, first + colon, s.baud);
  if (ec != std::errc() || end != first + colon || s.baud < 50) return std::nullopt;
  const auto parity = parse_parity(text.substr(colon + 2, 1));
  const char stop = text[colon + 3];
  if (!parity || (stop != '1' && stop != '2')) return std::nullopt;
  s.parity = *parity;
  s.stop_bits = static_cast<std::uint8_t>(stop - '0');
  return s;
}

}  // namespace rtu
