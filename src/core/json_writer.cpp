#include "core/json_writer.hpp"

#include <algorithm>
#include <cmath>

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
  out_.push_back('"');
  out_.append(name);
  out_.append(std::string_view("\":"));
  after_key_ = true;
}

namespace {

bool needs_escape(char c) {
  return c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20;
}

void append_integer(fmt::memory_buffer& out, const fmt::format_int& digits) {
  out.append(digits.data(), digits.data() + digits.size());
}

}  // namespace

void JsonWriter::value(std::string_view text) {
  separate();
  out_.push_back('"');
  // Names and units rarely hold anything to escape: those are copied whole.
  if (std::none_of(text.begin(), text.end(), needs_escape)) {
    out_.append(text);
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
  out_.append(b ? std::string_view("true") : std::string_view("false"));
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
  out_.append(std::string_view("null"));
}

void JsonWriter::value_raw(std::string_view json_text) {
  separate();
  out_.append(json_text);
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

}  // namespace rtu
