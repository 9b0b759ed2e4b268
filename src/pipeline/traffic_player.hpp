#pragma once
// Plays recorded traffic onto a virtual bus (the demo's simulated devices): the master's
// requests from one endpoint, the slaves' answers from another, at their recorded pace,
// on a thread of its own.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/time.hpp"

namespace rtu {

// One burst to put on the bus: who sends it and when (relative to the first).
struct Burst {
  Nanos at = 0;
  bool from_slave = false;
  std::vector<std::uint8_t> bytes;
};

class TrafficPlayer {
 public:
  // Opens both endpoints (throws InputError when one cannot be opened) and starts playing
  // `bursts`, `repeat` times over, paced for a line of `char_time` per character.
  TrafficPlayer(std::vector<Burst> bursts, unsigned repeat, const std::string& master_endpoint,
                const std::string& slave_endpoint, Nanos char_time);
  // Stops playing, waits for the thread and closes the endpoints.
  ~TrafficPlayer();
  TrafficPlayer(const TrafficPlayer&) = delete;
  TrafficPlayer& operator=(const TrafficPlayer&) = delete;

  // Plays no further burst. Safe from any thread; idempotent.
  void stop();
  // Every burst was played (and the line was given time to carry the last), or stop() ended
  // the playing early.
  [[nodiscard]] bool done() const { return done_; }

 private:
  void play();
  // Sleeps until `deadline`; false when stop() came first.
  bool wait_until(std::chrono::steady_clock::time_point deadline);

  std::vector<Burst> bursts_;
  unsigned repeat_;
  Nanos char_time_;
  int master_fd_ = -1;
  int slave_fd_ = -1;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;  // guarded by mutex_
  std::atomic<bool> done_{false};
  std::thread thread_;
};

}  // namespace rtu
