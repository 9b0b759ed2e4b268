#include "core/json_writer.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace rtu {
namespace {

std::string written(const std::vector<std::uint8_t>& bytes) {
  fmt::memory_buffer out;
  JsonWriter json(out);
  json.begin_object();
  json.field("a", 1U);
  json.key("values");
  json.u16_be_array(bytes);
  json.field("z", 2U);
  json.end_object();
  return fmt::to_string(out);
}

// Register values are written digit by digit in one go: every width, the extremes, an
// empty array and an odd trailing byte, with the separators around the array intact.
TEST(JsonWriter, BigEndianWordArray) {
  EXPECT_EQ(written({}), R"({"a":1,"values":[],"z":2})");
  EXPECT_EQ(written({0x00, 0x00}), R"({"a":1,"values":[0],"z":2})");
  EXPECT_EQ(written({0x00, 0x09, 0x00, 0x0A, 0x00, 0x63, 0x00, 0x64, 0x03, 0xE7, 0x03, 0xE8, 0x27,
                     0x0F, 0x27, 0x10, 0xFF, 0xFF}),
            R"({"a":1,"values":[9,10,99,100,999,1000,9999,10000,65535],"z":2})");
  EXPECT_EQ(written({0x12, 0x34, 0x56}), R"({"a":1,"values":[4660],"z":2})");
}

// Every 16-bit value reads back as the number it is.
TEST(JsonWriter, BigEndianWordArrayHoldsEveryValue) {
  std::vector<std::uint8_t> bytes;
  std::string expected = R"({"a":1,"values":[)";
  for (unsigned v = 0; v <= 0xFFFFU; ++v) {
    bytes.push_back(static_cast<std::uint8_t>(v >> 8U));
    bytes.push_back(static_cast<std::uint8_t>(v & 0xFFU));
    if (v > 0) expected += ',';
    expected += std::to_string(v);
  }
  expected += R"(],"z":2})";
  EXPECT_EQ(written(bytes), expected);
}

// Bytes as quoted lowercase hex, two digits each: every byte value, in a value of its own
// after a key, with an empty span as "".
TEST(JsonWriter, HexHoldsEveryByteValue) {
  std::vector<std::uint8_t> bytes;
  std::string expected = R"({"a":1,"hex":")";
  for (unsigned v = 0; v <= 0xFFU; ++v) {
    bytes.push_back(static_cast<std::uint8_t>(v));
    expected += fmt::format("{:02x}", v);
  }
  expected += R"(","empty":""})";
  fmt::memory_buffer out;
  JsonWriter json(out);
  json.begin_object();
  json.field("a", 1U);
  json.key("hex");
  json.hex(bytes);
  json.key("empty");
  json.hex({});
  json.end_object();
  EXPECT_EQ(fmt::to_string(out), expected);
}

// The escapes JSON requires, character by character, as RFC 8259 states them.
std::string escaped_by_the_book(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"') {
      out += "\\\"";
    } else if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (u < 0x20) {
      out += fmt::format("\\u{:04x}", u);
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string written_value(const std::string& text) {
  fmt::memory_buffer out;
  JsonWriter json(out);
  json.value(std::string_view(text));
  return fmt::to_string(out);
}

// Strings are checked for what to escape eight characters at a time: every character that
// needs it, and the neighbours of those that do not (0x1F/0x20, '!' and '#' beside '"', '['
// and ']' beside '\\', bytes of UTF-8), at every position of strings up to three words
// long, among plain letters and among bytes that borrow or carry in the word arithmetic.
TEST(JsonWriter, StringValuesAreEscapedWhereverTheCharacterFalls) {
  const std::string specials = std::string("\"\\\n\r\t") + '\0' + '\x01' + '\x1F';
  const std::string neighbours = std::string(" !#[]~\x7F") + '\x80' + '\xC3' + '\xA9' + '\xFF';
  for (const char filler : {'a', '\x20', '\xFF', '\x80'}) {
    for (std::size_t length = 1; length <= 24; ++length) {
      for (std::size_t at = 0; at < length; ++at) {
        for (const char c : specials + neighbours) {
          std::string text(length, filler);
          text[at] = c;
          ASSERT_EQ(written_value(text), escaped_by_the_book(text))
              << "length " << length << ", character 0x" << std::hex
              << unsigned{static_cast<unsigned char>(c)} << " at " << std::dec << at;
        }
      }
    }
  }
}

}  // namespace
}  // namespace rtu
