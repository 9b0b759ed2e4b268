#pragma once
// Warnings from capture readers: the input is usable, but something in it was adjusted and
// the user must know (e.g. a timestamp that went backwards). Readers never print themselves;
// they hand the message (already "FILE:LINE: ...") to a sink, so a caller that reads a file
// twice can silence the second pass and tests can collect the messages.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "core/time.hpp"

namespace rtu {

using WarningSink = std::function<void(std::string_view message)>;

// Prints "rtuscope: warning: <message>" to stderr.
void print_warning_to_stderr(std::string_view message);

// Keeps a reader's times in order. A time earlier than the previous one is clamped to the
// previous one (the bytes did arrive after the earlier ones, whatever the clock said: an
// NTP step, a writer that stamps from two threads) and the clamp is reported: the first
// kDetailed occurrences one by one, the rest as a count at finish().
class BackwardTimeClamp {
 public:
  static constexpr int kDetailed = 5;

  BackwardTimeClamp(std::string file, WarningSink sink);
  // `text` is the time as written in the input, for the message.
  Nanos admit(Nanos t, std::string_view text, std::uint64_t line);
  // Reports the occurrences not yet reported one by one. Call at the end of the input; only
  // the first call reports.
  void finish();
  [[nodiscard]] std::uint64_t clamped() const { return clamped_; }

 private:
  std::string file_;
  WarningSink sink_;
  bool have_last_ = false;
  Nanos last_ = 0;
  std::string last_text_;
  std::uint64_t last_line_ = 0;
  std::uint64_t clamped_ = 0;
  bool finished_ = false;
};

// The same for records that are found by their offset in a binary file (pcap, pcapng): the
// message names the offset, and the times are shown in seconds since 1970.
class RecordTimeClamp {
 public:
  static constexpr int kDetailed = BackwardTimeClamp::kDetailed;

  RecordTimeClamp(std::string file, WarningSink sink);
  Nanos admit(Nanos t, std::uint64_t offset);
  void finish();
  [[nodiscard]] std::uint64_t clamped() const { return clamped_; }

 private:
  std::string file_;
  WarningSink sink_;
  bool have_last_ = false;
  Nanos last_ = 0;
  std::uint64_t last_offset_ = 0;
  std::uint64_t clamped_ = 0;
  bool finished_ = false;
};

}  // namespace rtu
