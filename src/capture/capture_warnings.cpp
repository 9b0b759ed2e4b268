#include "capture/capture_warnings.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <cstring>
#include <utility>

#include "core/time_format.hpp"

namespace rtu {

void print_warning_to_stderr(std::string_view message) {
  fmt::print(stderr, "rtuscope: warning: {}\n", message);
}

namespace {
std::string seconds_text(Nanos t) {
  fmt::memory_buffer out;
  append_seconds(out, t);
  return fmt::to_string(out);
}
}  // namespace

BackwardTimeClamp::BackwardTimeClamp(std::string file, WarningSink sink)
    : file_(std::move(file)), sink_(std::move(sink)) {}

Nanos BackwardTimeClamp::clamp(std::string_view text, std::uint64_t line) {
  if (clamped_ <= kDetailed && sink_) {
    sink_(fmt::format("{}:{}: timestamp goes backwards ({} after {} on line {}); using {}", file_,
                      line, text, last_text(), last_position_, last_text()));
  }
  return last_;  // last_text() and last_position_ keep naming the time in force
}

Nanos BackwardTimeClamp::admit_at_offset(Nanos t, std::uint64_t offset) {
  if (goes_backwards(t)) {
    if (clamped_ <= kDetailed && sink_) {
      sink_(
          fmt::format("{}: offset {}: timestamp goes backwards ({} s after {} s at offset {}); "
                      "using {} s",
                      file_, offset, seconds_text(t), seconds_text(last_), last_position_,
                      seconds_text(last_)));
    }
    return last_;
  }
  have_last_ = true;
  last_ = t;
  last_position_ = offset;
  return t;
}

void BackwardTimeClamp::finish() {
  if (finished_) return;
  finished_ = true;
  if (clamped_ > kDetailed && sink_) {
    sink_(fmt::format("{}: {} more timestamps went backwards and were clamped ({} in all)", file_,
                      clamped_ - kDetailed, clamped_));
  }
}

}  // namespace rtu
