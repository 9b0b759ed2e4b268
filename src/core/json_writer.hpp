#pragma once
// Minimal streaming JSON writer over a reusable fmt buffer: no allocation once the buffer
// has grown to the size of the largest record. Keys are written as given (callers pass
// plain ASCII identifiers); string values are escaped.
#include <fmt/format.h>

#include <cstdint>
#include <span>
#include <string_view>

#include "core/short_copy.hpp"

namespace rtu {

class JsonWriter {
 public:
  explicit JsonWriter(fmt::memory_buffer& out) : out_(out) {}

  // What every field of every record goes through is defined inline below: as calls they
  // cost more than the few bytes each writes (a JSONL record is some 20 fields).
  void begin_object() { open('{'); }
  void end_object() { close('}'); }
  void begin_array() { open('['); }
  void end_array() { close(']'); }
  void key(std::string_view name);  // next value belongs to this key

  void value(std::string_view text);
  void value(const char* text) { value(std::string_view(text)); }
  void value(bool b) {
    separate();
    put(b ? std::string_view("true") : std::string_view("false"));
  }
  void value(std::int64_t n) {
    separate();
    put(fmt::format_int(n));
  }
  void value(std::uint64_t n) {
    separate();
    put(fmt::format_int(n));
  }
  void value(int n) { value(static_cast<std::int64_t>(n)); }
  void value(unsigned n) { value(static_cast<std::uint64_t>(n)); }
  // Fixed-point decimal with `decimals` digits after the point (no exponent form).
  void value_fixed(double x, int decimals);
  void value_double(double x);  // shortest round-trip form
  void null() {
    separate();
    put("null");
  }
  // A value already rendered as JSON (e.g. an exact decimal); written as is.
  void value_raw(std::string_view json_text) {
    separate();
    put(json_text);
  }
  // For a value rendered straight into the output (e.g. an exact decimal): the buffer to
  // append its JSON text to, once the separator before it is written. Saves a copy on
  // values every record has.
  fmt::memory_buffer& raw_value_buffer() {
    separate();
    return out_;
  }
  void hex(std::span<const std::uint8_t> bytes);  // "0103..." lowercase, quoted
  // [w0,w1,...]: the unsigned 16-bit big-endian words of `bytes` (an odd last byte is left
  // out), written in one go: register values are most of what a decoded record holds.
  void u16_be_array(std::span<const std::uint8_t> bytes);

  template <typename T>
  void field(std::string_view name, T v) {
    key(name);
    value(v);
  }

 private:
  // The comma before a value, unless it follows its key or opens its object or array.
  void separate() {
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
  void open(char bracket) {
    separate();
    out_.push_back(bracket);
    ++depth_;
    has_items_ &= ~(std::uint64_t{1} << static_cast<unsigned>(depth_ - 1));
  }
  void close(char bracket) {
    --depth_;
    out_.push_back(bracket);
  }
  // Lengthens the output by `n` characters and returns where they go: one size check for
  // a whole value, written in place. fmt's append() loops in pieces and is not inlined,
  // which costs more than the copy for the short keys and values of a record.
  char* grow(std::size_t n) {
    const std::size_t at = out_.size();
    out_.resize(at + n);
    return out_.data() + at;
  }
  void put(std::string_view text) { copy_short(grow(text.size()), text.data(), text.size()); }
  // An integer's digits (at most 20 and a sign): the bounded copy lets the compiler see that
  // nothing past format_int's buffer is read.
  void put(const fmt::format_int& digits) {
    copy_at_most_32(grow(digits.size()), digits.data(), digits.size());
  }

  fmt::memory_buffer& out_;
  // One bit per nesting level: whether a value was already written at that level.
  std::uint64_t has_items_ = 0;
  int depth_ = 0;
  bool after_key_ = false;
};

inline void JsonWriter::key(std::string_view name) {
  separate();
  char* p = grow(name.size() + 3);
  *p++ = '"';
  copy_short(p, name.data(), name.size());
  p += name.size();
  *p++ = '"';
  *p = ':';
  after_key_ = true;
}

}  // namespace rtu
