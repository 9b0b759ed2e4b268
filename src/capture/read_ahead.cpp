#include "capture/read_ahead.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <utility>

namespace rtu {

// One thing the reader delivered; its bytes live in its batch's arena.
struct ReadAhead::Item {
  enum class Kind : std::uint8_t { kChunk, kFrame, kNoise, kEnd };
  Kind kind = Kind::kChunk;
  std::uint8_t port = 0;
  bool has_errors = false;
  Nanos t = 0;  // a chunk's t_end; a frame's or noise's t_start; the end's time
  Nanos t_first_start = kUnknownTime;
  std::uint64_t origin = 0;
  std::size_t at = 0;  // first byte in Batch::bytes (and Batch::errors, when it has errors)
  std::size_t size = 0;
};

struct ReadAhead::Batch {
  std::vector<Item> items;
  std::vector<std::uint8_t> bytes;
  std::vector<std::uint8_t> errors;  // parallel to bytes where an item has errors
  std::uint64_t bytes_read = 0;      // the reader's progress once the batch was full
  bool last = false;                 // the reader ended (or failed) after these items
  std::exception_ptr error;          // how it failed, thrown after the items

  void clear() {
    items.clear();
    bytes.clear();
    errors.clear();
    bytes_read = 0;
    last = false;
    error = nullptr;
  }
  [[nodiscard]] bool full() const {
    return items.size() >= kBatchItems || bytes.size() >= kBatchBytes;
  }
};

// Copies what the reader delivers into a batch.
class ReadAhead::Collector final : public CaptureConsumer {
 public:
  explicit Collector(Batch& batch) : batch_(batch) {}
  // Items are filled in place in the batch: one built on the stack and copied in was
  // stored and reloaded in pieces of different widths, which stalls the copy.
  void on_chunk(const Chunk& chunk) override {
    Item& item = bytes_item(Item::Kind::kChunk, chunk.bytes, chunk.t_end, chunk.origin);
    item.t_first_start = chunk.t_first_start;
    item.port = chunk.port;
    if (!chunk.errors.empty()) {
      item.has_errors = true;
      // Errors sit at the same positions as their bytes; other items' places stay zero.
      batch_.errors.resize(batch_.bytes.size(), 0);
      std::copy(chunk.errors.begin(), chunk.errors.end(),
                batch_.errors.begin() + static_cast<std::ptrdiff_t>(item.at));
    }
  }
  void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) override {
    bytes_item(Item::Kind::kFrame, adu, t_start, origin);
  }
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) override {
    bytes_item(Item::Kind::kNoise, bytes, t_start, origin);
  }
  void on_end(Nanos t) override {
    Item& item = batch_.items.emplace_back();
    item.kind = Item::Kind::kEnd;
    item.t = t;
  }

 private:
  Item& bytes_item(Item::Kind kind, std::span<const std::uint8_t> bytes, Nanos t,
                   std::uint64_t origin) {
    Item& item = batch_.items.emplace_back();
    item.kind = kind;
    item.t = t;
    item.origin = origin;
    item.at = batch_.bytes.size();
    item.size = bytes.size();
    batch_.bytes.insert(batch_.bytes.end(), bytes.begin(), bytes.end());
    return item;
  }
  Batch& batch_;
};

// Hands each item to the consumer alongside, then to the batch.
class ReadAhead::Tee final : public CaptureConsumer {
 public:
  Tee(CaptureConsumer& first, CaptureConsumer& then) : first_(first), then_(then) {}
  void on_chunk(const Chunk& chunk) override {
    first_.on_chunk(chunk);
    then_.on_chunk(chunk);
  }
  void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) override {
    first_.on_frame(adu, t_start, origin);
    then_.on_frame(adu, t_start, origin);
  }
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) override {
    first_.on_noise(bytes, t_start, origin);
    then_.on_noise(bytes, t_start, origin);
  }
  void on_end(Nanos t) override {
    first_.on_end(t);
    then_.on_end(t);
  }

 private:
  CaptureConsumer& first_;
  CaptureConsumer& then_;
};

ReadAhead::ReadAhead(std::unique_ptr<CaptureReader> reader, CaptureConsumer* alongside)
    : reader_(std::move(reader)),
      alongside_(alongside),
      name_(reader_->name()),
      input_size_(reader_->input_size()) {
  for (std::size_t i = 0; i < kBatches; ++i) free_.push_back(std::make_unique<Batch>());
  thread_ = std::thread([this] { run(); });
}

ReadAhead::~ReadAhead() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

std::unique_ptr<ReadAhead::Batch> ReadAhead::next_free() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [this] { return stopping_ || !free_.empty(); });
  if (stopping_) return nullptr;
  auto batch = std::move(free_.back());
  free_.pop_back();
  return batch;
}

void ReadAhead::run() {
  for (;;) {
    auto batch = next_free();
    if (batch == nullptr) return;
    batch->clear();
    Collector collector(*batch);
    std::optional<Tee> tee;
    if (alongside_ != nullptr) tee.emplace(*alongside_, collector);
    CaptureConsumer& to = tee ? static_cast<CaptureConsumer&>(*tee) : collector;
    try {
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
    batch->bytes_read = reader_->bytes_read();
    const bool last = batch->last;
    {
      const std::lock_guard lock(mutex_);
      ready_.push_back(std::move(batch));
    }
    changed_.notify_all();
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
  const std::span<const std::uint8_t> bytes(batch.bytes.data() + item.at, item.size);
  switch (item.kind) {
    case Item::Kind::kChunk: {
      Chunk chunk;
      chunk.t_end = item.t;
      chunk.t_first_start = item.t_first_start;
      chunk.bytes = bytes;
      if (item.has_errors) chunk.errors = {batch.errors.data() + item.at, item.size};
      chunk.origin = item.origin;
      chunk.port = item.port;
      to.on_chunk(chunk);
      break;
    }
    case Item::Kind::kFrame: to.on_frame(bytes, item.t, item.origin); break;
    case Item::Kind::kNoise: to.on_noise(bytes, item.t, item.origin); break;
    case Item::Kind::kEnd: to.on_end(item.t); break;
  }
}

bool ReadAhead::read(CaptureConsumer& to) {
  for (;;) {
    if (ended_) return false;
    if (current_ != nullptr && next_item_ < current_->items.size()) {
      deliver(current_->items[next_item_++], *current_, to);
      return true;
    }
    if (current_ != nullptr) {
      // Everything of this batch is out: its end, or its failure, comes next.
      if (current_->last) {
        ended_ = true;
        if (current_->error) std::rethrow_exception(current_->error);
        return false;
      }
      {
        const std::lock_guard lock(mutex_);
        free_.push_back(std::move(current_));
      }
      changed_.notify_all();
    }
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !ready_.empty(); });
    current_ = std::move(ready_.front());
    ready_.pop_front();
    next_item_ = 0;
    bytes_read_ = current_->bytes_read;
  }
}

}  // namespace rtu
