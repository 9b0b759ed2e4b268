#pragma once
// Batches handed from one producing thread to one consuming thread, from a fixed pool: the
// producer fills a free batch and publishes it, the consumer takes the batches in the order
// they were published and gives each back once it is done with it. Memory stays bounded by
// the pool, and the producer waits whenever the consumer is a whole pool behind.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

namespace rtu {

template <typename Batch>
class HandoffQueue {
 public:
  explicit HandoffQueue(std::size_t batches) {
    for (std::size_t i = 0; i < batches; ++i) free_.push_back(std::make_unique<Batch>());
  }

  // A free batch for the producer to fill, as it was given back; null once stop() was called.
  std::unique_ptr<Batch> acquire() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return stopping_ || !free_.empty(); });
    if (stopping_) return nullptr;
    auto batch = std::move(free_.back());
    free_.pop_back();
    return batch;
  }
  void publish(std::unique_ptr<Batch> batch) {
    {
      const std::lock_guard lock(mutex_);
      ready_.push_back(std::move(batch));
    }
    changed_.notify_all();
  }
  // The oldest published batch; waits for one.
  std::unique_ptr<Batch> take() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !ready_.empty(); });
    auto batch = std::move(ready_.front());
    ready_.pop_front();
    return batch;
  }
  void give_back(std::unique_ptr<Batch> batch) {
    {
      const std::lock_guard lock(mutex_);
      free_.push_back(std::move(batch));
    }
    changed_.notify_all();
  }
  // The consumer is going away: acquire() answers null from now on, waking a waiting producer.
  void stop() {
    {
      const std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::unique_ptr<Batch>> ready_;  // published, oldest first
  std::vector<std::unique_ptr<Batch>> free_;
  bool stopping_ = false;
};

}  // namespace rtu
