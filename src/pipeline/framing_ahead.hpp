#pragma once
// Reads and frames a capture on a second thread, a batch ahead of the pairing: the reader's
// parsing, the framers and the port merge run on one core while the transaction tracker and
// everything after it (device decoding, statistics, writers) run on the calling thread.
// That splits a replay's work about evenly between two cores, where reading ahead alone
// left most of it on the decoding one.
//
// The tracker is told exactly what a DecodePipeline's own tracker would be told (capture
// start, records, decided times, finish), in the same order and with the same contents,
// but for a decided time that the next record's start covers (the tracker advances to that
// start itself), and an `on_chunk` callback sees each raw read at the same point of that
// sequence as in CaptureFeed; so the output of a run never depends on the threads.
//
// Memory is bounded: at most kBatches batches of about kBatchSteps steps or kBatchBytes raw
// bytes exist at a time (a batch is checked between reader items, and a ReadAhead inside
// hands over a run of at most its kBatchItems one-byte reads as one item). Fewer, larger
// handoffs matter where a third thread (a ReadAhead inside) shares the two cores.
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "capture/capture_reader.hpp"
#include "core/handoff_queue.hpp"
#include "framing/capture_info.hpp"
#include "pairing/pairing_input.hpp"
#include "pipeline/decode_pipeline.hpp"

namespace rtu {

class FramingAhead {
 public:
  static constexpr std::size_t kBatches = 6;
  static constexpr std::size_t kBatchSteps = 4096;
  static constexpr std::size_t kBatchBytes = 64 * 1024;

  struct Setup {
    PipelineOptions pipeline;
    CaptureInfo info;        // told to the pairing before the first record
    bool use_chunks = true;  // raw reads are re-framed, else frame records (see CaptureFeed)
    // Sees each raw read, on the calling thread, just before the records its bytes made.
    std::function<void(const Chunk&)> on_chunk;
  };

  // Starts reading and framing `reader` at once. `alongside` (optional, not owned) sees every
  // item the reader delivers as well, on the reading thread: a survey that costs the
  // decoding core nothing. It is the reading thread's until deliver() has returned false or
  // thrown.
  FramingAhead(std::unique_ptr<CaptureReader> reader, Setup setup,
               CaptureConsumer* alongside = nullptr);
  // Stops the reading thread (reading need not have reached the end) and waits for it.
  ~FramingAhead();
  FramingAhead(const FramingAhead&) = delete;
  FramingAhead& operator=(const FramingAhead&) = delete;
  FramingAhead(FramingAhead&&) = delete;
  FramingAhead& operator=(FramingAhead&&) = delete;

  // Tells `pairing` (the same one on every call) the next batch of what the framing found.
  // False once the capture's end was told (its on_finish); a reader's exception is thrown
  // then, after everything read before it was told and finished.
  bool deliver(PairingInput& pairing);

  [[nodiscard]] const Setup& setup() const { return setup_; }
  [[nodiscard]] std::string name() const { return name_; }
  // How far the reader had got by the batch delivered last, in input bytes and items (reads
  // and records).
  [[nodiscard]] std::uint64_t bytes_read() const { return bytes_read_; }
  [[nodiscard]] std::uint64_t items_read() const { return items_read_; }
  [[nodiscard]] std::uint64_t input_size() const { return input_size_; }

  // True once deliver() has returned false or thrown: the reading thread is done.
  [[nodiscard]] bool ended() const { return ended_; }
  // The reader itself, for what it learned by the end (declarations, capture warnings).
  // Only once ended(); throws std::logic_error before.
  [[nodiscard]] const CaptureReader& source();
  // The timing resolution the framing ended with (DecodePipeline::timing_resolution); only
  // once ended().
  [[nodiscard]] Nanos resolution_at_end() const { return resolution_at_end_; }

 private:
  struct Step;
  struct ChunkItem;
  struct Batch;
  class Handoff;

  void run();  // the reading thread
  void tell(Batch& batch, PairingInput& pairing) const;

  std::unique_ptr<CaptureReader> reader_;
  Setup setup_;
  CaptureConsumer* alongside_;
  std::string name_;
  std::uint64_t input_size_ = 0;
  std::uint64_t bytes_read_ = 0;
  std::uint64_t items_read_ = 0;

  std::unique_ptr<HandoffQueue<Batch>> queue_;
  std::unique_ptr<Batch> current_;  // being told (the reading thread never touches it)
  bool ended_ = false;
  Nanos resolution_at_end_ = 0;
  std::thread thread_;  // last: started once everything above exists
};

}  // namespace rtu
