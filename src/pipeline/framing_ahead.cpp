#include "pipeline/framing_ahead.hpp"

#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "capture/byte_arena.hpp"
#include "capture/consumer_tee.hpp"
#include "core/thread_name.hpp"
#include "pipeline/capture_feed.hpp"

namespace rtu {

// One call the pairing is to get, in order.
struct FramingAhead::Step {
  enum class Kind : std::uint8_t { kCapture, kChunk, kRecord, kAdvance, kBreak, kFinish };
  Kind kind = Kind::kRecord;
  Nanos t = 0;            // kAdvance: decided until
  std::size_t index = 0;  // kChunk: into Batch::chunks; kRecord: into Batch::records
};

// A raw read for the on_chunk callback; its bytes (and errors) live in its batch's arena.
struct FramingAhead::ChunkItem {
  Nanos t_end = 0;
  Nanos t_first_start = kUnknownTime;
  std::uint64_t origin = 0;
  std::uint8_t port = 0;
  bool time_clamped = false;
  bool read_late = false;
  Nanos quiet_until = kUnknownTime;
  ByteArena::Run run;
};

struct FramingAhead::Batch {
  std::vector<Step> steps;
  // Advances the next record covered (Handoff::on_record): they count towards a full batch
  // as the steps they were, so a batch holds as many records as it did with them.
  std::size_t advances_untold = 0;
  // Kept across batches so each Record is built once; the first `records_used` are this
  // batch's.
  std::vector<Record> records;
  std::size_t records_used = 0;
  std::vector<ChunkItem> chunks;
  ByteArena arena;
  std::optional<CaptureInfo> capture;
  std::uint64_t bytes_read = 0;  // the reader's progress once the batch was full
  std::uint64_t items_read = 0;  // reads and records in this batch
  bool last = false;             // the capture's end was told in it
  std::exception_ptr error;      // how reading failed, thrown after the steps
  Nanos resolution_at_end = 0;   // the framing's, in the last batch

  void clear() {
    steps.clear();
    advances_untold = 0;
    records_used = 0;
    chunks.clear();
    arena.clear();
    capture.reset();
    bytes_read = 0;
    items_read = 0;
    last = false;
    error = nullptr;
    resolution_at_end = 0;
  }
  [[nodiscard]] bool full() const {
    return steps.size() + advances_untold >= kBatchSteps || arena.size() >= kBatchBytes;
  }
};

// The framing half's pairing: writes each call into the batch being filled.
class FramingAhead::Handoff final : public PairingInput {
 public:
  void fill(Batch& batch) { batch_ = &batch; }

  void on_capture(const CaptureInfo& info) override {
    tell_advance();
    batch_->capture = info;
    batch_->steps.push_back(Step{Step::Kind::kCapture, 0, 0});
  }
  void on_record(Record& record) override {
    // The tracker's on_record() first advances to the record's start: an advance to no later
    // than that, right before it, does exactly what that does (a request times out either
    // way before the record is handled), and need not cross the threads (one a read).
    Batch& batch = *batch_;
    if (advance_pending_) {
      if (advanced_ > record.t_start) {
        tell_advance();
      } else {
        ++batch.advances_untold;
        advance_pending_ = false;
      }
    }
    if (batch.records_used == batch.records.size()) batch.records.emplace_back();
    batch.records[batch.records_used].copy_in_use(record);
    batch.steps.push_back(Step{Step::Kind::kRecord, 0, batch.records_used++});
    record_since_advance_ = true;
  }
  // The tracker's advance() only compares `now` with the waiting request's deadline, so
  // with no record between, a call no later than the previous one does nothing, and two
  // calls in a row act as the later one alone: such calls need not cross the threads (one
  // per read otherwise). The latest is held until the next step shows whether it is needed.
  void advance(Nanos now) override {
    if (!record_since_advance_ && now <= advanced_) return;
    advanced_ = now;
    record_since_advance_ = false;
    advance_pending_ = true;
  }
  void on_finish() override {
    tell_advance();
    batch_->steps.push_back(Step{Step::Kind::kFinish, 0, 0});
  }
  void on_break() override {
    tell_advance();
    batch_->steps.push_back(Step{Step::Kind::kBreak, 0, 0});
    record_since_advance_ = true;  // an advance after it is told, whatever came before
  }

  // The advance held, as a step of its own; called before any step but a record, and at the
  // end of each batch.
  void tell_advance() {
    if (!advance_pending_) return;
    batch_->steps.push_back(Step{Step::Kind::kAdvance, advanced_, 0});
    advance_pending_ = false;
  }

  void on_chunk(const Chunk& chunk) {
    tell_advance();
    Batch& batch = *batch_;
    ChunkItem& item = batch.chunks.emplace_back();
    item.t_end = chunk.t_end;
    item.t_first_start = chunk.t_first_start;
    item.origin = chunk.origin;
    item.port = chunk.port;
    item.time_clamped = chunk.time_clamped;
    item.read_late = chunk.read_late;
    item.quiet_until = chunk.quiet_until;
    item.run = batch.arena.add(chunk.bytes, chunk.errors);
    batch.steps.push_back(Step{Step::Kind::kChunk, 0, batch.chunks.size() - 1});
  }

 private:
  Batch* batch_ = nullptr;
  Nanos advanced_ = 0;
  bool record_since_advance_ = true;
  bool advance_pending_ = false;  // advanced_ is still to be told
};

FramingAhead::FramingAhead(std::unique_ptr<CaptureReader> reader, Setup setup,
                           CaptureConsumer* alongside)
    : reader_(std::move(reader)),
      setup_(std::move(setup)),
      alongside_(alongside),
      name_(reader_->name()),
      input_size_(reader_->input_size()),
      queue_(std::make_unique<HandoffQueue<Batch>>(kBatches)) {
  thread_ = std::thread([this] { run(); });
}

FramingAhead::~FramingAhead() {
  if (!thread_.joinable()) return;
  queue_->stop();
  thread_.join();
}

void FramingAhead::run() {
  name_this_thread("rtu-framing");
  Handoff handoff;
  DecodePipeline framing(setup_.pipeline, handoff);
  std::function<void(const Chunk&)> tap;
  if (setup_.on_chunk) tap = [&handoff](const Chunk& chunk) { handoff.on_chunk(chunk); };
  CaptureFeed feed(framing, setup_.use_chunks, setup_.info.line.char_time(), std::move(tap));
  std::optional<ConsumerTee> tee;
  if (alongside_ != nullptr) tee.emplace(*alongside_, feed);
  CaptureConsumer& to = tee ? static_cast<CaptureConsumer&>(*tee) : feed;
  bool started = false;
  std::uint64_t items_before = 0;
  for (;;) {
    auto batch = queue_->acquire();
    if (batch == nullptr) return;
    batch->clear();
    handoff.fill(*batch);
    try {
      if (!started) {
        started = true;
        framing.start(setup_.info);
      }
      while (!batch->full()) {
        if (!reader_->read(to)) {
          batch->last = true;
          break;
        }
      }
    } catch (...) {
      batch->last = true;
      batch->error = std::current_exception();
    }
    // Reads, not reader items: a run of one-byte reads is one item (ReadAhead).
    batch->items_read = feed.items() - items_before;
    items_before = feed.items();
    if (batch->last) {
      // Everything read before the end or the damage is still framed and told.
      try {
        framing.finish();
      } catch (...) {
        if (!batch->error) batch->error = std::current_exception();
      }
      batch->resolution_at_end = framing.timing_resolution();
    }
    handoff.tell_advance();
    batch->bytes_read = reader_->bytes_read();
    const bool last = batch->last;
    queue_->publish(std::move(batch));
    if (last) return;
  }
}

void FramingAhead::tell(Batch& batch, PairingInput& pairing) const {
  for (const Step& step : batch.steps) {
    switch (step.kind) {
      case Step::Kind::kCapture: pairing.on_capture(*batch.capture); break;
      case Step::Kind::kChunk: {
        const ChunkItem& item = batch.chunks[step.index];
        Chunk chunk;
        chunk.t_end = item.t_end;
        chunk.t_first_start = item.t_first_start;
        chunk.bytes = batch.arena.bytes(item.run);
        chunk.errors = batch.arena.errors(item.run);
        chunk.origin = item.origin;
        chunk.port = item.port;
        chunk.time_clamped = item.time_clamped;
        chunk.read_late = item.read_late;
        chunk.quiet_until = item.quiet_until;
        setup_.on_chunk(chunk);
        break;
      }
      case Step::Kind::kRecord:
        // The batch is this thread's until given back: the record is told as it lies.
        pairing.on_record(batch.records[step.index]);
        break;
      case Step::Kind::kAdvance: pairing.advance(step.t); break;
      case Step::Kind::kBreak: pairing.on_break(); break;
      case Step::Kind::kFinish: pairing.on_finish(); break;
    }
  }
}

bool FramingAhead::deliver(PairingInput& pairing) {
  if (ended_) return false;
  if (current_ != nullptr) queue_->give_back(std::move(current_));
  current_ = queue_->take();
  bytes_read_ = current_->bytes_read;
  items_read_ += current_->items_read;
  const bool last = current_->last;
  if (last) {
    ended_ = true;  // the reading thread is done even if telling throws
    resolution_at_end_ = current_->resolution_at_end;
  }
  tell(*current_, pairing);
  if (!last) return true;
  if (current_->error) std::rethrow_exception(current_->error);
  return false;
}

const CaptureReader& FramingAhead::source() {
  if (!ended_) throw std::logic_error("FramingAhead::source() asked before reading ended");
  // The thread's last act on the reader came before it handed over the last batch; joining
  // makes that plain.
  if (thread_.joinable()) thread_.join();
  return *reader_;
}

}  // namespace rtu
