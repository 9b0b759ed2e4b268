#include "core/crc16.hpp"

namespace rtu {
std::uint16_t crc16(std::span<const std::uint8_t> bytes, std::uint16_t crc) {
  for (const std::uint8_t b : bytes) crc = crc16_update(crc, b);
  return crc;
}

bool crc16_valid(std::span<const std::uint8_t> adu) {
  return adu.size() >= 3 && crc16(adu) == 0;
}

}  // namespace rtu
