#pragma once
// Reads a capture on a second thread, a batch ahead of the decoding, so that the reader's
// parsing (most of what a text capture costs) runs on one core while framing, pairing and
// the statistics run on the other. The items come out exactly as the reader gives them, in
// the same order and with the same contents, so everything downstream sees what a direct
// read would give: the output of a run never depends on the threads.
//
// Memory is bounded: at most kBatches batches of at most kBatchItems items or kBatchBytes
// bytes exist at a time (about 2 MB each). Batches are that large because a per-byte capture
// makes an item of every byte: with three threads on two cores (a ReadAhead inside a
// FramingAhead), small batches made each handoff a wait for a core, and 4,096 items cost a
// per-byte report 15% of its time in the switching.
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "capture/capture_reader.hpp"
#include "core/handoff_queue.hpp"

namespace rtu {

// How a ReadAhead hands over what it reads, and how its thread behaves.
struct ReadAheadOptions {
  // Sees every item as well (optional, not owned), on the reading thread, just before it is
  // batched: a survey that costs the decoding core nothing. It is the reading thread's until
  // read() has returned false or thrown.
  CaptureConsumer* alongside = nullptr;
  // False: the reader's frame and noise records are not handed over (only `alongside` sees
  // them), for a consumer that re-frames the raw reads and leaves them aside.
  bool hand_over_records = true;
  // One-byte reads in a row go out as one item (on_byte_reads), up to a batch's worth,
  // instead of one read() each; for a consumer that reads to the end and never needs to stop
  // between two reads.
  bool whole_byte_runs = false;
  // The threads of the pipeline whose lightest this reading thread is, itself included (the
  // replay's parsing, framing and pairing: 3), or 0. Where they outnumber the cores, the
  // reading thread lowers its priority so that the busiest keeps its core (a per-byte report:
  // 5-7% less wall time on two).
  std::size_t yields_among_threads = 0;
};

class ReadAhead final : public CaptureReader {
 public:
  static constexpr std::size_t kBatches = 6;
  static constexpr std::size_t kBatchItems = 32768;
  static constexpr std::size_t kBatchBytes = 512 * 1024;

  // Starts reading `reader` at once. Only read(), name(), bytes_read() and input_size() may
  // be asked of this object: the reader's other answers belong to the survey pass, or to
  // source() once reading ended.
  explicit ReadAhead(std::unique_ptr<CaptureReader> reader, ReadAheadOptions options = {});
  // Stops the reading thread (reading need not have reached the end) and waits for it.
  ~ReadAhead() override;
  ReadAhead(const ReadAhead&) = delete;
  ReadAhead& operator=(const ReadAhead&) = delete;
  ReadAhead(ReadAhead&&) = delete;
  ReadAhead& operator=(ReadAhead&&) = delete;

  // As CaptureReader::read: the reader's exception is thrown here once every item read
  // before it was delivered, and after it read() returns false.
  bool read(CaptureConsumer& to) override;

  [[nodiscard]] std::string name() const override { return name_; }
  // As far as the items delivered so far reach (the reader itself is a batch further on).
  [[nodiscard]] std::uint64_t bytes_read() const override { return bytes_read_; }
  [[nodiscard]] std::uint64_t input_size() const override { return input_size_; }

  // True once read() has returned false or thrown: the reading thread is done.
  [[nodiscard]] bool ended() const { return ended_; }
  // The reader itself, for what it learned by the end (declarations, capture warnings).
  // Only once ended(); throws std::logic_error before.
  [[nodiscard]] const CaptureReader& source();

 private:
  struct Item;
  struct Batch;
  class Collector;

  void run();  // the reading thread
  void deliver(const Item& item, const Batch& batch, CaptureConsumer& to);
  // The next one-byte read of a run: true when it was the run's last.
  bool deliver_byte_read(const Item& item, const Batch& batch, CaptureConsumer& to);
  // All one-byte reads of a run at once (whole_byte_runs).
  static void deliver_byte_run(const Item& item, const Batch& batch, CaptureConsumer& to);

  std::unique_ptr<CaptureReader> reader_;
  ReadAheadOptions options_;
  std::string name_;
  std::uint64_t input_size_ = 0;
  std::uint64_t bytes_read_ = 0;

  std::unique_ptr<HandoffQueue<Batch>> queue_;
  std::unique_ptr<Batch> current_;  // being delivered (reading thread never touches it)
  std::size_t next_item_ = 0;
  std::uint32_t next_byte_ = 0;  // within a run of one-byte reads (Item::Kind::kByteReads)
  bool ended_ = false;
  std::thread thread_;  // last: started once everything above exists
};

}  // namespace rtu
