#pragma once
// Minimal streaming JSON writer over a reusable fmt buffer: no allocation once the buffer
// has grown to the size of the largest record. Keys are written as given (callers pass
// plain ASCII identifiers); string values are escaped.
#include <fmt/format.h>

#include <cstdint>
#include <span>
#include <string_view>

namespace rtu {

class JsonWriter {
 public:
  explicit JsonWriter(fmt::memory_buffer& out) : out_(out) {}

  void begin_object();
  void end_object();
  void begin_array();
  void end_array();
  void key(std::string_view name);  // next value belongs to this key

  void value(std::string_view text);
  void value(const char* text) { value(std::string_view(text)); }
  void value(bool b);
  void value(std::int64_t n);
  void value(std::uint64_t n);
  void value(int n) { value(static_cast<std::int64_t>(n)); }
  void value(unsigned n) { value(static_cast<std::uint64_t>(n)); }
  // Fixed-point decimal with `decimals` digits after the point (no exponent form).
  void value_fixed(double x, int decimals);
  void value_double(double x);  // shortest round-trip form
  void null();
  // A value already rendered as JSON (e.g. an exact decimal); written as is.
  void value_raw(std::string_view json_text);
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
  void separate();
  fmt::memory_buffer& out_;
  // One bit per nesting level: whether a value was already written at that level.
  std::uint64_t has_items_ = 0;
  int depth_ = 0;
  bool after_key_ = false;
};

}  // namespace rtu
