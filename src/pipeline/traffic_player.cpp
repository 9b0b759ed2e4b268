#include "pipeline/traffic_player.hpp"

#include <unistd.h>

#include <algorithm>
#include <thread>
#include <utility>

#include "core/thread_name.hpp"
#include "serial/virtual_bus.hpp"

namespace rtu {

TrafficPlayer::TrafficPlayer(std::vector<Burst> bursts, unsigned repeat,
                             const std::string& master_endpoint, const std::string& slave_endpoint,
                             Nanos char_time)
    : bursts_(std::move(bursts)), repeat_(repeat), char_time_(char_time) {
  master_fd_ = open_bus_endpoint(master_endpoint);
  try {
    slave_fd_ = open_bus_endpoint(slave_endpoint);
  } catch (...) {
    ::close(master_fd_);
    throw;
  }
  thread_ = std::thread([this] {
    name_this_thread("rtu-player");
    play();
    done_ = true;
  });
}

TrafficPlayer::~TrafficPlayer() {
  stop();
  thread_.join();
  ::close(master_fd_);
  ::close(slave_fd_);
}

void TrafficPlayer::stop() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
}

bool TrafficPlayer::wait_until(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock lock(mutex_);
  return !wake_.wait_until(lock, deadline, [this] { return stopping_; });
}

// Long silences are shortened to 200 ms. A burst is never written before the previous one
// has left the wire: when this thread runs late (a loaded machine), bursts from the
// master's and the slaves' endpoints would otherwise wait side by side and the bus could
// take them in the wrong order.
void TrafficPlayer::play() {
  constexpr Nanos kMaxSilence = 200 * kNanosPerMilli;
  auto next = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
  auto wire_free = next;
  for (unsigned round = 0; round < repeat_; ++round) {
    Nanos previous = 0;
    for (const auto& burst : bursts_) {
      next += std::chrono::nanoseconds(std::min(burst.at - previous, kMaxSilence));
      previous = burst.at;
      next = std::max(next, wire_free);
      if (!wait_until(next)) {
        // Stopped: the burst still on the wire reaches the listener before done() says so.
        std::this_thread::sleep_until(wire_free);
        return;
      }
      const int fd = burst.from_slave ? slave_fd_ : master_fd_;
      [[maybe_unused]] const auto n = ::write(fd, burst.bytes.data(), burst.bytes.size());
      // On the wire until then, plus a character of margin for the bus to pick it up.
      wire_free = std::chrono::steady_clock::now() +
                  std::chrono::nanoseconds(char_time_ * static_cast<Nanos>(burst.bytes.size() + 1));
    }
    next += std::chrono::milliseconds(100);
  }
  // Time for the last answer to cross the bus (or the last request to time out) before the
  // listener is told the playing is over.
  wait_until(next + std::chrono::milliseconds(300));
}

}  // namespace rtu
