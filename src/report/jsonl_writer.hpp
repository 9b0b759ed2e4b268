#pragma once
// JSON Lines output: one object per record, in time order, preceded by a "capture" header.
// The keys are a public interface (scripts depend on them): add, never rename.
//
//   header: kind="capture", source, baud, parity, stop_bits, char_time_us, t1_5_us, t3_5_us,
//           timing_resolution_ms, per_byte_timing, response_timeout_ms, note
//   frame:  kind="frame", t, t_end (seconds, input clock), gap_ms (null when not observable),
//           hex, slave, fc, function, crc_ok, role, txn (null when unmatched), latency_ms
//           (responses), exception {code, name}, issues [keys], decoded fields, device keys
//   noise:  kind="noise", t, t_end, gap_ms, hex, issues
#include <fmt/format.h>

#include "core/output_stream.hpp"
#include "framing/record.hpp"

namespace rtu {

class JsonlWriter : public RecordSink {
 public:
  // Each record is handed to `out` whole; when it reaches the file is `out`'s choice.
  explicit JsonlWriter(OutputStream& out);

  void on_capture(const CaptureInfo& info) override;
  void on_record(Record& record) override;
  void on_finish() override;

 private:
  OutputStream& out_;
  fmt::memory_buffer buffer_;
};

}  // namespace rtu
