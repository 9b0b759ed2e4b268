#include "capture/read_ahead.hpp"

#include <algorithm>
#include <exception>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "capture/byte_arena.hpp"
#include "capture/consumer_tee.hpp"
#include "core/thread_name.hpp"
#include "core/thread_priority.hpp"

namespace rtu {
namespace {

constexpr int kNiceStepsBelowFraming = 3;

}  // namespace

// One thing the reader delivered; its bytes live in its batch's arena.
// Its small fields last, so that they share the run's padding: 40 bytes, not 56 (a per-byte
// capture makes an item of every byte).
//
// A per-byte capture's reads (one byte each, no line error, no start time, one after the
// other on one port) share one item of kind kByteReads: its run holds their bytes, and the
// batch's byte_times their end times from index `t` on. Each read costs the handover 9
// bytes instead of a 48-byte item, and most of a per-byte decoding's reading thread was the
// writing of those items.
struct ReadAhead::Item {
  enum class Kind : std::uint8_t { kChunk, kFrame, kNoise, kEnd, kByteReads };
  // A chunk's t_end; a frame's or noise's t_start; the end's time; for kByteReads, the index
  // of its first read's time in Batch::byte_times.
  Nanos t = 0;
  Nanos t_first_start = kUnknownTime;
  std::uint64_t origin = 0;
  ByteArena::Run run;
  Kind kind = Kind::kChunk;
  std::uint8_t port = 0;
  bool time_clamped = false;         // a chunk's
  bool read_late = false;            // a chunk's
  Nanos quiet_until = kUnknownTime;  // a chunk's
};

struct ReadAhead::Batch {
  std::vector<Item> items;
  ByteArena arena;
  // The end times of the reads of kByteReads items, in order: byte_time_count of them. A
  // batch is full at kBatchItems, so their room is fixed and a time is stored unchecked,
  // once per byte of a per-byte capture. Not zeroed: a capture of other reads never touches
  // (so never maps) it.
  std::unique_ptr<Nanos[]> byte_times = std::make_unique_for_overwrite<Nanos[]>(kBatchItems);
  std::size_t byte_time_count = 0;
  std::uint64_t bytes_read = 0;  // the reader's progress once the batch was full
  bool last = false;             // the reader ended (or failed) after these items
  std::exception_ptr error;      // how it failed, thrown after the items

  void clear() {
    items.clear();
    arena.clear();
    byte_time_count = 0;
    bytes_read = 0;
    last = false;
    error = nullptr;
  }
  [[nodiscard]] bool full() const {
    return items.size() >= kBatchItems || byte_time_count >= kBatchItems ||
           arena.size() >= kBatchBytes;
  }
};

// Copies what the reader delivers into a batch.
class ReadAhead::Collector final : public CaptureConsumer {
 public:
  Collector(Batch& batch, bool records) : batch_(batch), records_(records) {}
  // Items are filled in place in the batch: one built on the stack and copied in was
  // stored and reloaded in pieces of different widths, which stalls the copy.
  void on_chunk(const Chunk& chunk) override {
    if (ByteReads::holds(chunk)) {
      // A run of one read: it extends the last item where that is a run it continues.
      on_byte_reads(ByteReads{chunk.bytes, &chunk.t_end, chunk.origin, chunk.port});
      return;
    }
    Item& item = new_item(Item::Kind::kChunk, chunk.t_end, chunk.origin);
    item.t_first_start = chunk.t_first_start;
    item.port = chunk.port;
    item.time_clamped = chunk.time_clamped;
    item.read_late = chunk.read_late;
    item.quiet_until = chunk.quiet_until;
    item.run = batch_.arena.add(chunk.bytes, chunk.errors);
  }
  void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) override {
    if (records_) new_item(Item::Kind::kFrame, t_start, origin).run = batch_.arena.add(adu);
  }
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) override {
    if (records_) new_item(Item::Kind::kNoise, t_start, origin).run = batch_.arena.add(bytes);
  }
  void on_end(Nanos t) override { new_item(Item::Kind::kEnd, t, 0); }
  // A run of one-byte reads at once, extending the last item where that is a run this one
  // continues; the batch has room for its times (run()).
  void on_byte_reads(const ByteReads& reads) override {
    const std::size_t n = reads.size();
    if (n == 0) return;
    Item* item = batch_.items.empty() ? nullptr : &batch_.items.back();
    if (item != nullptr && item->kind == Item::Kind::kByteReads && item->port == reads.port &&
        item->origin + item->run.size == reads.origin) {
      batch_.arena.extend(item->run, reads.bytes);
    } else {
      item = &new_item(Item::Kind::kByteReads, static_cast<Nanos>(batch_.byte_time_count),
                       reads.origin);
      item->port = reads.port;
      item->run = batch_.arena.add(reads.bytes);
    }
    std::copy(reads.t_ends, reads.t_ends + n, batch_.byte_times.get() + batch_.byte_time_count);
    batch_.byte_time_count += n;
  }

 private:
  Item& new_item(Item::Kind kind, Nanos t, std::uint64_t origin) {
    Item& item = batch_.items.emplace_back();
    item.kind = kind;
    item.t = t;
    item.origin = origin;
    return item;
  }
  Batch& batch_;
  bool records_;
};

ReadAhead::ReadAhead(std::unique_ptr<CaptureReader> reader, ReadAheadOptions options)
    : reader_(std::move(reader)),
      options_(options),
      name_(reader_->name()),
      input_size_(reader_->input_size()),
      queue_(std::make_unique<HandoffQueue<Batch>>(kBatches)) {
  thread_ = std::thread([this] { run(); });
}

ReadAhead::~ReadAhead() {
  if (!thread_.joinable()) return;
  queue_->stop();
  thread_.join();
}

void ReadAhead::run() {
  name_this_thread("rtu-read");
  // Three threads on two cores share them evenly whenever all three can run, and parsing,
  // the lightest, then runs ahead while framing, the busiest, waits for a core; later the
  // parsing has filled its batches and the pairing has emptied its own, and only the framing
  // runs while a core idles. Three nice levels below the others, parsing takes its share
  // where the framing leaves one (per-byte report: 2 to 4 levels gave the least wall time).
  if (options_.yields_among_threads > 0) {
    yield_priority_if_crowded(options_.yields_among_threads, kNiceStepsBelowFraming);
  }
  for (;;) {
    auto batch = queue_->acquire();
    if (batch == nullptr) return;
    batch->clear();
    Collector collector(*batch, options_.hand_over_records);
    std::optional<ConsumerTee> tee;
    if (options_.alongside != nullptr) tee.emplace(*options_.alongside, collector);
    CaptureConsumer& to = tee ? static_cast<CaptureConsumer&>(*tee) : collector;
    try {
      while (!batch->full()) {
        // Runs of one-byte reads come whole, up to the room left for their times.
        if (!reader_->read_many(to, kBatchItems - batch->byte_time_count)) {
          batch->last = true;
          break;
        }
      }
    } catch (...) {
      batch->last = true;
      batch->error = std::current_exception();
    }
    batch->bytes_read = reader_->bytes_read();
    const bool last = batch->last;
    queue_->publish(std::move(batch));
    if (last) return;
  }
}

const CaptureReader& ReadAhead::source() {
  if (!ended_) throw std::logic_error("ReadAhead::source() asked before reading ended");
  // The thread's last act on the reader came before it handed over the last batch; joining
  // makes that plain.
  if (thread_.joinable()) thread_.join();
  return *reader_;
}

void ReadAhead::deliver(const Item& item, const Batch& batch, CaptureConsumer& to) {
  static_assert(sizeof(Item) <= 48, "one item per read of a batched capture: keep it small");
  const std::span<const std::uint8_t> bytes = batch.arena.bytes(item.run);
  switch (item.kind) {
    case Item::Kind::kChunk: {
      Chunk chunk;
      chunk.t_end = item.t;
      chunk.t_first_start = item.t_first_start;
      chunk.time_clamped = item.time_clamped;
      chunk.read_late = item.read_late;
      chunk.quiet_until = item.quiet_until;
      chunk.bytes = bytes;
      chunk.errors = batch.arena.errors(item.run);
      chunk.origin = item.origin;
      chunk.port = item.port;
      to.on_chunk(chunk);
      break;
    }
    case Item::Kind::kFrame: to.on_frame(bytes, item.t, item.origin); break;
    case Item::Kind::kNoise: to.on_noise(bytes, item.t, item.origin); break;
    case Item::Kind::kEnd: to.on_end(item.t); break;
    case Item::Kind::kByteReads: break;  // one read at a time: deliver_byte_read
  }
}

bool ReadAhead::deliver_byte_read(const Item& item, const Batch& batch, CaptureConsumer& to) {
  const std::uint32_t i = next_byte_;
  Chunk chunk;
  chunk.t_end = batch.byte_times[static_cast<std::size_t>(item.t) + i];
  chunk.bytes = batch.arena.bytes(item.run).subspan(i, 1);
  chunk.origin = item.origin + i;
  chunk.port = item.port;
  to.on_chunk(chunk);
  if (++next_byte_ < item.run.size) return false;
  next_byte_ = 0;
  return true;
}

void ReadAhead::deliver_byte_run(const Item& item, const Batch& batch, CaptureConsumer& to) {
  ByteReads reads;
  reads.bytes = batch.arena.bytes(item.run);
  reads.t_ends = batch.byte_times.get() + static_cast<std::size_t>(item.t);
  reads.origin = item.origin;
  reads.port = item.port;
  to.on_byte_reads(reads);
}

bool ReadAhead::read(CaptureConsumer& to) {
  for (;;) {
    if (ended_) return false;
    if (current_ != nullptr && next_item_ < current_->items.size()) {
      const Item& item = current_->items[next_item_];
      if (item.kind == Item::Kind::kByteReads) {
        if (options_.whole_byte_runs) {
          deliver_byte_run(item, *current_, to);
          ++next_item_;
        } else if (deliver_byte_read(item, *current_, to)) {
          ++next_item_;
        }
      } else {
        deliver(item, *current_, to);
        ++next_item_;
      }
      return true;
    }
    if (current_ != nullptr) {
      // Everything of this batch is out: its end, or its failure, comes next.
      if (current_->last) {
        ended_ = true;
        if (current_->error) std::rethrow_exception(current_->error);
        return false;
      }
      queue_->give_back(std::move(current_));
    }
    current_ = queue_->take();
    next_item_ = 0;
    bytes_read_ = current_->bytes_read;
  }
}

}  // namespace rtu
