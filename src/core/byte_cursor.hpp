#pragma once
// Bounds-checked big-endian reader over a byte span, for decoding untrusted frames.
// Reads past the end never touch memory: they return 0 (or a shorter span) and make the
// cursor fail, so a decoder can read a whole layout and check ok() once at the end.
// The cursor does not own the bytes; spans it returns point into the original storage.
#include <cstddef>
#include <cstdint>
#include <span>

namespace rtu {

class ByteCursor {
 public:
  constexpr ByteCursor() = default;
  constexpr explicit ByteCursor(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  [[nodiscard]] constexpr std::size_t position() const { return pos_; }
  [[nodiscard]] constexpr std::size_t remaining() const { return bytes_.size() - pos_; }
  [[nodiscard]] constexpr bool has(std::size_t n) const { return n <= remaining(); }
  [[nodiscard]] constexpr bool at_end() const { return pos_ == bytes_.size(); }
  // False once any read asked for more bytes than were left.
  [[nodiscard]] constexpr bool ok() const { return ok_; }

  constexpr std::uint8_t u8() {
    if (!has(1)) return fail();
    return bytes_[pos_++];
  }

  constexpr std::uint16_t u16() {  // big-endian, as every Modbus field
    if (!has(2)) return fail();
    const auto value =
        static_cast<std::uint16_t>((unsigned{bytes_[pos_]} << 8U) | unsigned{bytes_[pos_ + 1]});
    pos_ += 2;
    return value;
  }

  // Exactly n bytes; when fewer are left, returns what is left and fails.
  constexpr std::span<const std::uint8_t> take(std::size_t n) {
    if (!has(n)) {
      ok_ = false;
      return take_up_to(n);
    }
    return take_up_to(n);
  }

  // Up to n bytes, without failing when fewer are left.
  constexpr std::span<const std::uint8_t> take_up_to(std::size_t n) {
    const std::size_t count = n < remaining() ? n : remaining();
    const auto out = bytes_.subspan(pos_, count);
    pos_ += count;
    return out;
  }

  // Everything that is left.
  constexpr std::span<const std::uint8_t> rest() { return take_up_to(remaining()); }

 private:
  constexpr std::uint8_t fail() {
    ok_ = false;
    pos_ = bytes_.size();  // later reads fail too: fields never come from shifted bytes
    return 0;
  }

  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace rtu
