#pragma once
// CRC-16/MODBUS (reflected poly 0x8005 = 0xA001, init 0xFFFF, no final xor), appended to
// an ADU low byte first. Running it over a whole ADU including its CRC yields 0.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace rtu {

inline constexpr std::uint16_t kCrcInit = 0xFFFF;

namespace crc_detail {
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

// Slicing by eight: kSlices[k][i] is the CRC register after byte i is followed by k zero
// bytes, so eight bytes are folded in with eight independent lookups instead of a chain of
// eight dependent ones.
constexpr std::array<std::array<std::uint16_t, 256>, 8> make_slices() {
  std::array<std::array<std::uint16_t, 256>, 8> slices{};
  slices[0] = make_table();
  for (std::size_t k = 1; k < slices.size(); ++k) {
    for (std::size_t i = 0; i < 256; ++i) {
      const std::uint16_t prev = slices[k - 1][i];
      slices[k][i] = static_cast<std::uint16_t>((prev >> 8U) ^ slices[0][prev & 0xFFU]);
    }
  }
  return slices;
}
inline constexpr std::array<std::array<std::uint16_t, 256>, 8> kSlices = make_slices();
// The byte-at-a-time table is the first slice.
inline constexpr const std::array<std::uint16_t, 256>& kTable = kSlices[0];
}  // namespace crc_detail

// Continues a CRC over one more byte; start with kCrcInit. Inline: the framer's CRC scans
// call it for every byte of every candidate length.
inline std::uint16_t crc16_update(std::uint16_t crc, std::uint8_t byte) {
  return static_cast<std::uint16_t>((crc >> 8U) ^ crc_detail::kTable[(crc ^ byte) & 0xFFU]);
}
std::uint16_t crc16(std::span<const std::uint8_t> bytes, std::uint16_t crc = kCrcInit);

// True when the last two bytes are the CRC of the bytes before them.
bool crc16_valid(std::span<const std::uint8_t> adu);

}  // namespace rtu
