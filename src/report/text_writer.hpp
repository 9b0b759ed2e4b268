#pragma once
// Human-readable output: one aligned line per record.
//
//        time [s]        gap  role slave function         summary ... latency  issues
//   12.345678901   +50.123ms  req    1  read holding     0x0032 ×3
#include <fmt/format.h>

#include "core/output_stream.hpp"
#include "framing/record.hpp"

namespace rtu {

class TextWriter : public RecordSink {
 public:
  // Each record is handed to `out` whole; when it reaches the file is `out`'s choice.
  explicit TextWriter(OutputStream& out);

  void on_capture(const CaptureInfo& info) override;
  void on_record(Record& record) override;
  void on_finish() override;

 private:
  OutputStream& out_;
  fmt::memory_buffer buffer_;
  Nanos shown_day_ = kUnknownTime;  // UTC day of the last date line (wall-clock captures)
};

// The frame's readable summary (what it asks or answers), without device annotations.
void append_frame_summary(fmt::memory_buffer& out, const Record& frame);

}  // namespace rtu
