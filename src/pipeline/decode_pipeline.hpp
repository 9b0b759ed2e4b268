#pragma once
// The one decode path shared by replay and live capture:
//   chunks → Framer → TransactionTracker → RecordSink (text, JSONL, reports, exports).
// It never reads a clock: all time comes from the chunks.
#include <memory>
#include <optional>
#include <span>

#include "capture/chunk_source.hpp"
#include "core/chunk.hpp"
#include "framing/capture_info.hpp"
#include "framing/record.hpp"
#include "pairing/pairing_input.hpp"

namespace rtu {

class Framer;

struct PipelineOptions {
  LineSettings line;
  Nanos response_timeout = 1000 * kNanosPerMilli;
  // Timing resolution of the input; kUnknownTime = estimate it (see TimingEstimator).
  Nanos timing_resolution = kUnknownTime;
  bool per_byte_timing = false;
  // The framer may raise the resolution from what the reads show (off when the user fixed it).
  bool learn_resolution = true;
};

class DecodePipeline {
 public:
  DecodePipeline(const PipelineOptions& options, RecordSink& sink);
  // The framing half alone: records and decided times go to `pairing` (a handoff to a
  // tracker on another thread) instead of to a tracker of its own. awaits_idle() and
  // next_idle_decision() then answer as if a request might be waiting.
  DecodePipeline(const PipelineOptions& options, PairingInput& pairing);
  ~DecodePipeline();
  DecodePipeline(const DecodePipeline&) = delete;
  DecodePipeline& operator=(const DecodePipeline&) = delete;

  // Header to the sink; called automatically before the first record if not called.
  void start(const CaptureInfo& info);
  void push(const Chunk& chunk);
  // One push() for each of `reads`, in order; the loop runs here, with the port's framer
  // found once.
  void push_byte_reads(const ByteReads& reads);
  // A frame whose boundaries are already known (e.g. imported from a pcap with
  // LINKTYPE_WIRESHARK_UPPER_PDU): bypasses the framer, still CRC-checked and paired.
  // Longer than kMaxAdu, it is split, never cut: a CRC-valid one becomes a `too_long`
  // frame of its first kMaxAdu bytes plus noise, any other goes through a framer of its
  // own (glued frames become frames, the rest noise).
  void push_frame(std::span<const std::uint8_t> adu, Nanos t_start, Nanos t_end,
                  std::uint64_t origin);
  // Bytes already known to form no frame (imported noise records): a noise record, as
  // the framer would have emitted it.
  void push_noise(std::span<const std::uint8_t> bytes, Nanos t_start, Nanos t_end,
                  std::uint64_t origin);
  // No read completed before `now` (input clock): frames waiting for more bytes are
  // decided once that is Framer::decidable_at() (t3.5 + resolution, at least
  // kDeliveryPatience, after the last byte; see Framer::quiet_to_decide()), and a request
  // older than the response timeout is released as timed out.
  // push() does the same with each chunk's time before its bytes; a live capture also
  // calls it while the line is quiet. Both decide at the same point of the byte stream,
  // so a live run and the replay of its recording give identical records.
  void idle(Nanos now);
  // Whether an idle() call could still decide something: a framer or the merge holds
  // bytes or records, or a request waits for its answer or its timeout. When not, idle()
  // has nothing to do until the next push(), so a live capture need not wake up for it.
  [[nodiscard]] bool awaits_idle() const;
  // The earliest moment an idle() call could decide what is held now: the line quiet long
  // enough after the held bytes, or a waiting request's timeout with the delivery delay
  // after it. kUnknownTime when that cannot be told (idle() may then be tried at any time).
  [[nodiscard]] Nanos next_idle_decision() const;
  // The timing resolution in force now (raised from the configured one by what was learned).
  [[nodiscard]] Nanos timing_resolution() const;
  // Flushes partial frames and open transactions.
  void finish();
  // The capture stopped and goes on after an unknown time (a recording's end followed by
  // another file): what is held is decided as finish() decides it, but the sink goes on,
  // and the next bytes show no silence before them (none was observed).
  void break_capture();

 private:
  // start() with what the options say, for input that comes before any start().
  void start_as_configured();
  // A non-empty read, to its port's `framer`.
  void push_read(Framer& framer, const Chunk& chunk);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Line settings the user gave: they win over what a capture declares, which wins over the
// Modbus default 9600 8E1.
struct LineOverrides {
  std::optional<std::uint32_t> baud;
  std::optional<Parity> parity;
  std::optional<std::uint8_t> stop_bits;
  // --baud auto: infer the rate (and character size) from the capture's timing even where
  // the capture declares it (see pipeline/line_inference.hpp).
  bool infer_baud = false;
};

}  // namespace rtu
