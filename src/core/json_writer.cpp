#include "core/json_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/short_copy.hpp"

namespace rtu {

void JsonWriter::separate() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (depth_ > 0) {
    const std::uint64_t bit = std::uint64_t{1} << static_cast<unsigned>(depth_ - 1);
    if ((has_items_ & bit) != 0) out_.push_back(',');
    has_items_ |= bit;
  }
}

void JsonWriter::begin_object() {
  separate();
  out_.push_back('{');
  ++depth_;
  has_items_ &= ~(std::uint64_t{1} << static_cast<unsigned>(depth_ - 1));
}

void JsonWriter::end_object() {
  --depth_;
  out_.push_back('}');
}

void JsonWriter::begin_array() {
  separate();
  out_.push_back('[');
  ++depth_;
  has_items_ &= ~(std::uint64_t{1} << static_cast<unsigned>(depth_ - 1));
}

void JsonWriter::end_array() {
  --depth_;
  out_.push_back(']');
}

void JsonWriter::key(std::string_view name) {
  separate();
  const std::size_t at = out_.size();
  out_.resize(at + name.size() + 3);
  char* p = out_.data() + at;
  *p++ = '"';
  copy_short(p, name.data(), name.size());
  p += name.size();
  *p++ = '"';
  *p = ':';
  after_key_ = true;
}

namespace {

bool needs_escape(char c) {
  return c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20;
}

// Appends `text` with one size check and one copy: fmt's append() loops in pieces and is
// not inlined, which costs more than the copy for the short keys and values of a record.
void put(fmt::memory_buffer& out, std::string_view text) {
  const std::size_t at = out.size();
  out.resize(at + text.size());
  copy_short(out.data() + at, text.data(), text.size());
}

void append_integer(fmt::memory_buffer& out, const fmt::format_int& digits) {
  put(out, std::string_view(digits.data(), digits.size()));
}

}  // namespace

void JsonWriter::value(std::string_view text) {
  separate();
  out_.push_back('"');
  // Names and units rarely hold anything to escape: those are copied whole.
  if (std::none_of(text.begin(), text.end(), needs_escape)) {
    put(out_, text);
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

void JsonWriter::value(bool b) {
  separate();
  put(out_, b ? std::string_view("true") : std::string_view("false"));
}

void JsonWriter::value(std::int64_t n) {
  separate();
  append_integer(out_, fmt::format_int(n));
}

void JsonWriter::value(std::uint64_t n) {
  separate();
  append_integer(out_, fmt::format_int(n));
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

void JsonWriter::null() {
  separate();
  put(out_, "null");
}

void JsonWriter::value_raw(std::string_view json_text) {
  separate();
  put(out_, json_text);
}

void JsonWriter::hex(std::span<const std::uint8_t> bytes) {
  separate();
  constexpr std::string_view kDigits = "0123456789abcdef";
  // Grown once, then written in place.
  const std::size_t at = out_.size();
  out_.resize(at + 2 + 2 * bytes.size());
  char* p = out_.data() + at;
  *p++ = '"';
  for (const std::uint8_t b : bytes) {
    *p++ = kDigits[b >> 4U];
    *p++ = kDigits[b & 0xFU];
  }
  *p = '"';
}

void JsonWriter::u16_be_array(std::span<const std::uint8_t> bytes) {
  separate();
  const std::size_t count = bytes.size() / 2;
  constexpr std::size_t kMaxChars = 6;  // "65535,"
  const std::size_t at = out_.size();
  out_.resize(at + 2 + count * kMaxChars);
  char* p = out_.data() + at;
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
