#pragma once
// Helpers for PDU tests: Records built from hex text, with or without an appended CRC.
#include <gtest/gtest.h>

#include <cctype>
#include <string>
#include <string_view>
#include <vector>

#include "core/crc16.hpp"
#include "core/json_writer.hpp"
#include "framing/record.hpp"
#include "modbus/pdu.hpp"

namespace rtu::test {

// "01 03 00 00" → bytes; spaces optional. Fails the test on bad hex.
inline Record frame_from_hex(std::string_view hex) {
  Record r;
  int high = -1;
  for (const char c : hex) {
    if (c == ' ') continue;
    const int digit = std::isdigit(static_cast<unsigned char>(c)) != 0 ? c - '0'
                      : (c >= 'a' && c <= 'f')                         ? c - 'a' + 10
                      : (c >= 'A' && c <= 'F')                         ? c - 'A' + 10
                                                                       : -1;
    EXPECT_GE(digit, 0) << "bad hex digit in " << hex;
    if (digit < 0) return r;
    if (high < 0) {
      high = digit;
    } else {
      r.storage.at(r.size++) = static_cast<std::uint8_t>(high * 16 + digit);
      high = -1;
    }
  }
  EXPECT_EQ(high, -1) << "odd number of hex digits in " << hex;
  r.crc_ok = crc16_valid(r.bytes());
  return r;
}

// Address + PDU in hex; the CRC is computed and appended (low byte first).
inline Record frame_with_crc(std::string_view hex) {
  Record r = frame_from_hex(hex);
  const std::uint16_t crc = crc16(r.bytes());
  r.storage.at(r.size++) = static_cast<std::uint8_t>(crc & 0xFFU);
  r.storage.at(r.size++) = static_cast<std::uint8_t>(crc >> 8U);
  r.crc_ok = true;
  return r;
}

inline std::string pdu_json(const DecodedPdu& pdu) {
  fmt::memory_buffer buf;
  JsonWriter json(buf);
  json.begin_object();
  write_pdu_json(json, pdu);
  json.end_object();
  return fmt::to_string(buf);
}

inline std::string pdu_summary(const DecodedPdu& pdu) {
  fmt::memory_buffer buf;
  append_pdu_summary(buf, pdu);
  return fmt::to_string(buf);
}

// The values of a view, for comparing with a list.
inline std::vector<unsigned> words(WordView v) {
  std::vector<unsigned> out;
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(v[i]);
  return out;
}

inline std::vector<int> bits(BitView v) {
  std::vector<int> out;
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(v[i] ? 1 : 0);
  return out;
}

}  // namespace rtu::test
