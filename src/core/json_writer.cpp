#include "core/json_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/byte_words.hpp"
#include "core/digit_pairs.hpp"
#include "core/short_copy.hpp"

namespace rtu {

namespace {

bool needs_escape(char c) {
  return c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20;
}

// Whether `text` holds a character that JSON escapes; eight at a time (names of functions,
// roles, points and units: every record has several).
bool any_needs_escape(std::string_view text) {
  std::size_t i = 0;
  for (; i + 8 <= text.size(); i += 8) {
    const std::uint64_t word = byte_words::load(text.data() + i);
    // A quote or a backslash is a zero byte once XORed away; a control character is below 0x20.
    if (byte_words::has_byte_below(word ^ ('"' * byte_words::kOnes), 1) ||
        byte_words::has_byte_below(word ^ ('\\' * byte_words::kOnes), 1) ||
        byte_words::has_byte_below(word, 0x20)) {
      return true;
    }
  }
  return std::any_of(text.begin() + static_cast<std::ptrdiff_t>(i), text.end(), needs_escape);
}

}  // namespace

void JsonWriter::value(std::string_view text) {
  separate();
  out_.push_back('"');
  // Names and units rarely hold anything to escape: those are copied whole.
  if (!any_needs_escape(text)) {
    put(text);
    out_.push_back('"');
    return;
  }
  for (const char c : text) {
    switch (c) {
      case '"': out_.append(std::string_view("\\\"")); break;
      case '\\': out_.append(std::string_view("\\\\")); break;
      case '\n': out_.append(std::string_view("\\n")); break;
      case '\r': out_.append(std::string_view("\\r")); break;
      case '\t': out_.append(std::string_view("\\t")); break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          fmt::format_to(fmt::appender(out_), "\\u{:04x}", static_cast<unsigned>(c));
        } else {
          out_.push_back(c);
        }
    }
  }
  out_.push_back('"');
}

void JsonWriter::value_fixed(double x, int decimals) {
  if (!std::isfinite(x)) {
    null();
    return;
  }
  separate();
  fmt::format_to(fmt::appender(out_), "{:.{}f}", x, decimals);
}

void JsonWriter::value_double(double x) {
  if (!std::isfinite(x)) {
    null();
    return;
  }
  separate();
  fmt::format_to(fmt::appender(out_), "{}", x);
}

void JsonWriter::hex(std::span<const std::uint8_t> bytes) {
  separate();
  // Grown once, then written in place.
  char* p = grow(2 + 2 * bytes.size());
  *p++ = '"';
  for (const std::uint8_t b : bytes) {
    std::memcpy(p, hex_pair(b), 2);
    p += 2;
  }
  *p = '"';
}

void JsonWriter::u16_be_array(std::span<const std::uint8_t> bytes) {
  separate();
  const std::size_t count = bytes.size() / 2;
  constexpr std::size_t kMaxChars = 6;  // "65535,"
  char* p = grow(2 + count * kMaxChars);
  *p++ = '[';
  for (std::size_t i = 0; i < count; ++i) {
    if (i > 0) *p++ = ',';
    const fmt::format_int digits((unsigned{bytes[2 * i]} << 8U) | unsigned{bytes[2 * i + 1]});
    std::memcpy(p, digits.data(), digits.size());
    p += digits.size();
  }
  *p++ = ']';
  out_.resize(static_cast<std::size_t>(p - out_.data()));
}

}  // namespace rtu
