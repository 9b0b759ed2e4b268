#include "framing/crc_chain.hpp"

#include <bitset>

#include "core/crc16.hpp"
#include "framing/record.hpp"

namespace rtu {

bool holds_crc_chain(std::span<const std::uint8_t> bytes) {
  const std::size_t n = bytes.size();
  if (n < 2 * kMinAdu) return false;
  // Starts from the back, so that where a span [a, b) comes out CRC-valid, whether one
  // starts at b is already known.
  std::bitset<kMaxAdu + 1> valid_from;
  const std::size_t scanned = std::min(n, kMaxAdu);
  for (std::size_t a = scanned - kMinAdu + 1; a-- > 0;) {
    std::uint16_t crc = kCrcInit;
    const std::size_t end = a == 0 ? scanned - 1 : scanned;  // the whole is not one of them
    for (std::size_t b = a; b < end; ++b) {
      crc = crc16_update(crc, bytes[b]);
      if (crc != 0 || b + 1 - a < kMinAdu) continue;
      if (b + 1 < valid_from.size() && valid_from.test(b + 1)) return true;
      valid_from.set(a);
    }
  }
  return false;
}

}  // namespace rtu
