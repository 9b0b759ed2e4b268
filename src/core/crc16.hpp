#pragma once
// CRC-16/MODBUS (reflected poly 0x8005 = 0xA001, init 0xFFFF, no final xor), appended to
// an ADU low byte first. Running it over a whole ADU including its CRC yields 0.
#include <cstdint>
#include <span>

namespace rtu {

inline constexpr std::uint16_t kCrcInit = 0xFFFF;

// Continues a CRC over more bytes; start with kCrcInit.
std::uint16_t crc16_update(std::uint16_t crc, std::uint8_t byte);
std::uint16_t crc16(std::span<const std::uint8_t> bytes, std::uint16_t crc = kCrcInit);

// True when the last two bytes are the CRC of the bytes before them.
bool crc16_valid(std::span<const std::uint8_t> adu);

}  // namespace rtu
