#pragma once
// scan_plain_seconds() for the lines of one capture, which nearly all stamp alike: the same
// whole seconds as the line before (they change once a second) and the same number of
// decimals. The scanner keeps the last stamp's shape (where its point is, how long it is)
// and its whole seconds; a stamp of that shape with those whole seconds is read by checking
// its characters in place and reading only its decimals, eight at a time. Any other text
// goes to scan_plain_seconds(), whose answer it always gives (tests compare the two on
// random stamps), and teaches the shape anew.
//
// A per-byte capture has a line per wire byte: the general scan, two runs of digits each
// read eight at a time and then one by one, took half of its parsing thread's instructions
// (callgrind: 101 of 207 per line); in the shape, a stamp takes 55.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string_view>

#include "capture/plain_seconds.hpp"
#include "core/byte_words.hpp"
#include "core/time.hpp"

namespace rtu {

class StampShapeScanner {
 public:
  // As scan_plain_seconds(text, ns, decimals).
  std::size_t scan(std::string_view text, Nanos& ns, int& decimals) {
    if (const std::size_t length = scan_in_shape(text, ns, decimals); length > 0) return length;
    const std::size_t length = scan_plain_seconds(text, ns, decimals);
    learn(text, length, ns, decimals);
    return length;
  }

 private:
  // The shape is only taken where every word it loads lies inside `text`.
  static constexpr std::size_t kMinText = 16;
  static constexpr std::size_t kMinLength = 8;  // the decimals' word starts in the stamp

  // A mask of the first `count` (0-8) bytes of a word.
  static std::uint64_t first_bytes(std::size_t count) {
    return count >= 8 ? ~std::uint64_t{0} : (std::uint64_t{1} << (8 * count)) - 1;
  }

  std::size_t scan_in_shape(std::string_view text, Nanos& ns_out, int& decimals_out) const {
    using byte_words::kHighBits;
    using byte_words::kOnes;
    if (text.size() < min_text_) return 0;
    const char* const p = text.data();
    // The stamp ends where the last one did: its point in place, no digit after its decimals.
    if (p[dot_] != '.' || plain_seconds_detail::is_digit(p[length_])) return 0;
    // The same whole seconds, character for character.
    if (((byte_words::load(p) ^ whole_[0]) & whole_mask_[0]) != 0) return 0;
    if (whole_mask_[1] != 0 && ((byte_words::load(p + 8) ^ whole_[1]) & whole_mask_[1]) != 0) {
      return 0;
    }
    // The last (up to eight) decimals end the word that ends the stamp. XOR with '0' leaves a
    // digit's value in its byte; a byte is a digit when that is below 10 (adding 0x76 to its
    // low seven bits then keeps its top bit clear, and no byte carries into the next).
    const std::uint64_t values = byte_words::load(p + length_ - 8) ^ (0x30 * kOnes);
    const std::uint64_t tens = ((values & ~kHighBits) + 0x76 * kOnes) | values;
    if ((tens & kHighBits & tail_mask_) != 0) return 0;
    std::uint64_t fraction = plain_seconds_detail::digits_value(values & tail_mask_);
    if (ninth_decimal_) {
      if (!plain_seconds_detail::is_digit(p[dot_ + 1])) return 0;
      fraction += static_cast<std::uint64_t>(p[dot_ + 1] - '0') * 100'000'000U;
    }
    const std::uint64_t ns = whole_ns_ + fraction * fraction_scale_;
    if (may_pass_int64_ && ns > std::uint64_t{std::numeric_limits<Nanos>::max()}) return 0;
    ns_out = static_cast<Nanos>(ns);
    decimals_out = decimals_;
    return length_;
  }

  // After scan_plain_seconds() read `length` characters of `text` (0: nothing).
  void learn(std::string_view text, std::size_t length, Nanos ns, int decimals) {
    min_text_ = kNoShape;
    if (length < kMinLength || text.size() < kMinText || decimals < 1) return;
    const std::size_t dot = length - 1 - static_cast<std::size_t>(decimals);
    if (text[dot] != '.') return;
    length_ = length;
    dot_ = dot;
    decimals_ = decimals;
    whole_mask_[0] = first_bytes(dot);
    whole_mask_[1] = dot > 8 ? first_bytes(dot - 8) : 0;
    whole_[0] = byte_words::load(text.data()) & whole_mask_[0];
    whole_[1] = dot > 8 ? byte_words::load(text.data() + 8) & whole_mask_[1] : 0;
    const std::uint64_t whole = static_cast<std::uint64_t>(ns) / kNanosPerSecond;
    whole_ns_ = whole * kNanosPerSecond;
    // The word that ends the stamp holds its last min(decimals, 8) characters at its top.
    const auto digits = static_cast<std::size_t>(decimals);
    tail_mask_ = ~first_bytes(8 - (digits < 8 ? digits : 8));
    ninth_decimal_ = digits == 9;
    fraction_scale_ = plain_seconds_detail::kPowersOf10[9 - digits];
    may_pass_int64_ =
        whole_ns_ > std::uint64_t{std::numeric_limits<Nanos>::max()} - (kNanosPerSecond - 1);
    min_text_ = length < kMinText ? kMinText : length + 1;
  }

  static constexpr std::size_t kNoShape = ~std::size_t{0};
  // The text a stamp in the shape needs, at least: the stamp and a character after it, and
  // every word the reading loads (kNoShape: no shape to read in).
  std::size_t min_text_ = kNoShape;
  std::size_t length_ = 0;                // the last stamp's length
  std::size_t dot_ = 0;                   // where its point is (its whole digits before it: 0-10)
  int decimals_ = 0;                      // 1-9
  std::uint64_t whole_[2] = {0, 0};       // its whole seconds' characters, two words
  std::uint64_t whole_mask_[2] = {0, 0};  // which bytes of those words they are
  std::uint64_t tail_mask_ = 0;           // the decimals in the word ending the stamp
  bool ninth_decimal_ = false;            // one more decimal before that word
  std::uint64_t fraction_scale_ = 0;      // ns of the last decimal
  std::uint64_t whole_ns_ = 0;            // its whole seconds, in ns
  bool may_pass_int64_ = false;           // whole seconds so near int64 ns that a stamp may pass
};

}  // namespace rtu
