#pragma once
// The frame splitter: turns timed chunks into frames and noise records.
//
// Two kinds of evidence, used together:
//  * Silences between bytes, where the timestamps can show them. A chunk's bytes are
//    placed by counting back from its read time at the line rate, so only silences at
//    chunk boundaries are seen at all, and only to within the capture's timing resolution.
//  * What a frame's function code allows: the expected length in either role (request or
//    response, byte-count fields included), confirmed by the CRC. This is what survives
//    USB adapters that batch bytes into 16 ms transfers and glue requests to responses.
//
// A CRC-confirmed length-predicted frame always wins (it may even span a silence: that is
// a `t1.5` issue on the frame). When nothing at the head of the buffer is confirmed, the
// framer looks for the next position where a confirmed frame starts and classifies the
// bytes before it as a damaged frame (bad CRC, truncated) or, when they cannot be one,
// as noise. Bytes are never dropped: each ends up in exactly one record.
//
// Memory is fixed: a bounded byte window; nothing allocates per byte.
#include <array>
#include <bitset>
#include <cstdint>

#include "core/chunk.hpp"
#include "framing/record.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

struct FramerConfig {
  LineSettings line;
  // Silences shorter than this cannot be seen in the timestamps (see TimingEstimator).
  Nanos resolution = 0;
  // Chunks carry exact per-byte start times (logic analyser exports).
  bool per_byte_exact = false;
};

class Framer {
 public:
  // `out` receives every record, in time order. It must outlive the framer.
  Framer(const FramerConfig& config, RecordSink& out);

  void push(const Chunk& chunk);
  // The line has been silent since `now` (live capture): frames waiting for more bytes
  // can be decided. Replays need not call it.
  void idle(Nanos now);
  // End of input: everything still buffered is emitted.
  void finish();

  // Expected next frame, fed back by the transaction tracker's view of the bus; used
  // only to break ties between equally valid readings.
  void expect_response_from(std::uint8_t slave, std::uint8_t function);
  void expect_request();

 private:
  static constexpr std::size_t kWindow = 2048;             // bytes held while deciding
  static constexpr std::size_t kMaxPending = 4 * kMaxAdu;  // forces a decision beyond this

  struct ByteInfo {
    Nanos t_end = 0;
    Nanos gap_before = kUnknownTime;  // observable silence before this byte
    std::uint64_t origin = 0;
    std::uint8_t errors = 0;
  };

  enum class Verdict : std::uint8_t { kEmitted, kWait };

  void append_byte(std::uint8_t value, std::uint8_t errors, Nanos t_end, Nanos gap_before,
                   std::uint64_t origin);
  void decide(bool at_end);
  Verdict decide_head(bool at_end);

  // Length of a CRC-confirmed frame starting at `pos` (0 if none can be confirmed with
  // the bytes buffered now). `pending` is set when a predicted length needs more bytes.
  // `generic_depth` > 0 also accepts frames with no length rule, confirmed by their CRC and
  // by what follows them (a silence, or a further confirmed frame, up to that depth).
  std::size_t confirmed_length(std::size_t pos, bool at_end, int generic_depth,
                               bool* pending) const;
  std::size_t generic_crc_length(std::size_t pos, bool at_end, int depth, bool* pending) const;
  void classify_span(std::size_t length);
  bool boundary_at(std::size_t pos) const;
  bool plausible_start(std::size_t pos) const;
  bool awaited_response_at(std::size_t pos) const;
  std::size_t predicted_length(std::size_t pos) const;

  void emit_frame(std::size_t length);
  void emit_noise(std::size_t length);
  void flush_noise();
  void consume(std::size_t length);
  void fill_record(Record& rec, std::size_t from, std::size_t length) const;

  [[nodiscard]] std::size_t buffered() const { return end_ - begin_; }
  [[nodiscard]] std::uint8_t byte_at(std::size_t pos) const { return bytes_[begin_ + pos]; }
  [[nodiscard]] const ByteInfo& info_at(std::size_t pos) const { return info_[begin_ + pos]; }

  FramerConfig config_;
  RecordSink& out_;
  Nanos char_time_;
  Nanos t1_5_;
  Nanos t3_5_;

  std::array<std::uint8_t, kWindow> bytes_{};
  std::array<ByteInfo, kWindow> info_{};
  std::size_t begin_ = 0;
  std::size_t end_ = 0;

  Nanos last_byte_end_ = kUnknownTime;  // end of the newest byte pushed
  Nanos last_record_end_ = kUnknownTime;
  bool last_record_was_frame_ = false;
  // Positions [1, scan_resume_) of the window are known not to start a confirmable frame.
  std::size_t scan_resume_ = 1;
  std::bitset<256> active_slaves_;  // slaves seen in CRC-valid frames
  std::uint64_t next_seq_ = 0;

  Record noise_;  // noise bytes accumulate here until a frame follows or it is full
  Record scratch_;

  bool expect_response_ = false;
  std::uint8_t expected_slave_ = 0;
  std::uint8_t expected_function_ = 0;
};

}  // namespace rtu
