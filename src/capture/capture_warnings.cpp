#include "capture/capture_warnings.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <utility>

#include "core/time_format.hpp"

namespace rtu {

void print_warning_to_stderr(std::string_view message) {
  fmt::print(stderr, "rtuscope: warning: {}\n", message);
}

BackwardTimeClamp::BackwardTimeClamp(std::string file, WarningSink sink)
    : file_(std::move(file)), sink_(std::move(sink)) {}

Nanos BackwardTimeClamp::admit(Nanos t, std::string_view text, std::uint64_t line) {
  if (have_last_ && t < last_) {
    ++clamped_;
    if (clamped_ <= kDetailed && sink_) {
      sink_(fmt::format("{}:{}: timestamp goes backwards ({} after {} on line {}); using {}", file_,
                        line, text, last_text_, last_line_, last_text_));
    }
    return last_;  // last_text_ and last_line_ keep naming the time in force
  }
  have_last_ = true;
  last_ = t;
  last_text_.assign(text);
  last_line_ = line;
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

namespace {
std::string seconds_text(Nanos t) {
  fmt::memory_buffer out;
  append_seconds(out, t);
  return fmt::to_string(out);
}
}  // namespace

RecordTimeClamp::RecordTimeClamp(std::string file, WarningSink sink)
    : file_(std::move(file)), sink_(std::move(sink)) {}

Nanos RecordTimeClamp::admit(Nanos t, std::uint64_t offset) {
  if (have_last_ && t < last_) {
    ++clamped_;
    if (clamped_ <= kDetailed && sink_) {
      sink_(fmt::format(
          "{}: offset {}: timestamp goes backwards ({} s after {} s at offset {}); "
          "using {} s",
          file_, offset, seconds_text(t), seconds_text(last_), last_offset_, seconds_text(last_)));
    }
    return last_;  // last_offset_ keeps naming the record whose time is in force
  }
  have_last_ = true;
  last_ = t;
  last_offset_ = offset;
  return t;
}

void RecordTimeClamp::finish() {
  if (finished_) return;
  finished_ = true;
  if (clamped_ > kDetailed && sink_) {
    sink_(fmt::format("{}: {} more record timestamps went backwards and were clamped ({} in all)",
                      file_, clamped_ - kDetailed, clamped_));
  }
}

}  // namespace rtu
