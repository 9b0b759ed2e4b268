#pragma once
// Warnings from capture readers: the input is usable, but something in it was adjusted and
// the user must know (e.g. a timestamp that went backwards). Readers never print themselves;
// they hand the message (already "FILE:LINE: ...") to a sink, so a caller that reads a file
// twice can silence the second pass and tests can collect the messages.
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>

#include "core/short_copy.hpp"
#include "core/time.hpp"

namespace rtu {

using WarningSink = std::function<void(std::string_view message)>;

// Prints "rtuscope: warning: <message>" to stderr.
void print_warning_to_stderr(std::string_view message);

// Keeps a reader's times in order. A time earlier than the previous one is clamped to the
// previous one (the bytes did arrive after the earlier ones, whatever the clock said: an
// NTP step, a writer that stamps from two threads) and the clamp is reported: the first
// kDetailed occurrences one by one, the rest as a count at finish(). Text inputs name lines
// and show the times as written; binary ones (pcap, pcapng) name offsets and show seconds
// since 1970. A reader uses one of the two admit() forms.
class BackwardTimeClamp {
 public:
  static constexpr int kDetailed = 5;

  BackwardTimeClamp(std::string file, WarningSink sink);
  // `text` is the time as written in the input, for the message. Always inline (the
  // compiler left it out of line): a text capture admits a time at every line, and nearly
  // every one is in order.
  [[gnu::always_inline]] Nanos admit(Nanos t, std::string_view text, std::uint64_t line) {
    if (goes_backwards(t)) return clamp(text, line);
    have_last_ = true;
    last_ = t;
    last_in_place_ = {};
    keep(text);
    last_position_ = line;
    return t;
  }
  // As admit(), for a reader whose `text` (never empty) stays where it is until the reader
  // calls keep_text(): the text of the time in force is needed only if a later time goes
  // back, so it is not copied at every line (a per-byte capture's parsing thread spent an
  // eighth of its instructions copying stamps).
  [[gnu::always_inline]] Nanos admit_in_place(Nanos t, std::string_view text, std::uint64_t line) {
    if (goes_backwards(t)) return clamp(text, line);
    have_last_ = true;
    last_ = t;
    last_in_place_ = text;
    last_position_ = line;
    return t;
  }
  // The earliest time admit() and admit_in_place() take as it is (not clamped).
  [[nodiscard]] Nanos admits_from() const {
    return have_last_ ? last_ : std::numeric_limits<Nanos>::min();
  }
  // The text admit_in_place() was last given is about to change: it is copied now.
  void keep_text() {
    if (last_in_place_.empty()) return;
    keep(last_in_place_);
    last_in_place_ = {};
  }
  // A record at byte `offset` of a binary file.
  Nanos admit_at_offset(Nanos t, std::uint64_t offset);
  // Reports the occurrences not yet reported one by one. Call at the end of the input; only
  // the first call reports.
  void finish();
  [[nodiscard]] std::uint64_t clamped() const { return clamped_; }

 private:
  // True when `t` must be clamped to last_ (and then counts it).
  bool goes_backwards(Nanos t) {
    if (!have_last_ || t >= last_) return false;
    ++clamped_;
    return true;
  }
  // Reports a time of `text` on `line` that went back, and returns the time in force.
  Nanos clamp(std::string_view text, std::uint64_t line);

  std::string file_;
  WarningSink sink_;
  bool have_last_ = false;
  Nanos last_ = 0;
  // The time in force as written, for the message of a later time that goes back. It is
  // copied at every line of a text capture, so a short one (any stamp but an unusual one)
  // is kept in place rather than in a string.
  static constexpr std::size_t kShortText = 40;
  [[nodiscard]] std::string_view last_text() const {
    if (!last_in_place_.empty()) return last_in_place_;
    return last_text_size_ <= kShortText
               ? std::string_view(last_short_text_.data(), last_text_size_)
               : std::string_view(last_long_text_);
  }
  void keep(std::string_view text) {
    if (text.size() <= kShortText) {
      copy_short(last_short_text_.data(), text.data(), text.size());
    } else {
      last_long_text_.assign(text);
    }
    last_text_size_ = text.size();
  }
  std::array<char, kShortText> last_short_text_{};
  std::size_t last_text_size_ = 0;
  std::string last_long_text_;
  std::string_view last_in_place_;   // the text of admit_in_place(), where the reader keeps it
  std::uint64_t last_position_ = 0;  // its line, or its offset
  std::uint64_t clamped_ = 0;
  bool finished_ = false;
};

}  // namespace rtu
