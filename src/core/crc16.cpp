#include "core/crc16.hpp"

#include <array>

namespace rtu {
namespace {

constexpr std::array<std::uint16_t, 256> make_table() {
  std::array<std::uint16_t, 256> table{};
  for (unsigned i = 0; i < 256; ++i) {
    auto crc = static_cast<std::uint16_t>(i);
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 1U) != 0 ? static_cast<std::uint16_t>((crc >> 1U) ^ 0xA001U)
                            : static_cast<std::uint16_t>(crc >> 1U);
    }
    table[i] = crc;
  }
  return table;
}

constexpr auto kTable = make_table();

}  // namespace

std::uint16_t crc16_update(std::uint16_t crc, std::uint8_t byte) {
  return static_cast<std::uint16_t>((crc >> 8U) ^ kTable[(crc ^ byte) & 0xFFU]);
}

std::uint16_t crc16(std::span<const std::uint8_t> bytes, std::uint16_t crc) {
  for (const std::uint8_t b : bytes) crc = crc16_update(crc, b);
  return crc;
}

bool crc16_valid(std::span<const std::uint8_t> adu) {
  return adu.size() >= 3 && crc16(adu) == 0;
}

}  // namespace rtu
