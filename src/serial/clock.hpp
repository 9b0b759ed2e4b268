#pragma once
// The clocks of live capture. This module is the only code in rtuscope that reads a clock;
// everything downstream takes its time from the chunks, so replays and tests are exact.
//
// A capture's timeline is CLOCK_REALTIME at the start plus CLOCK_MONOTONIC elapsed since:
// gaps come from the monotonic clock (immune to NTP steps), while the times written to a
// capture file are still wall-clock nanoseconds since 1970, as pcapng wants.
#include "core/time.hpp"

namespace rtu {

struct ClockReading {
  Nanos monotonic = 0;  // CLOCK_MONOTONIC, ns
  Nanos wall = 0;       // CLOCK_REALTIME, ns since 1970-01-01 UTC
};

class Clock {
 public:
  virtual ~Clock() = default;
  virtual ClockReading now() = 0;
};

// The operating system's clocks.
class SystemClock final : public Clock {
 public:
  ClockReading now() override;
};

// Capture time: wall time at construction + monotonic time elapsed since. Shared by every
// port of one capture so their chunks merge on one timeline.
class CaptureClock {
 public:
  explicit CaptureClock(Clock& clock);
  // Capture time now (ns since 1970).
  Nanos now();
  // Capture time of an earlier reading of the same clock.
  [[nodiscard]] Nanos at(const ClockReading& reading) const {
    return anchor_.wall + (reading.monotonic - anchor_.monotonic);
  }
  [[nodiscard]] Clock& clock() { return clock_; }

 private:
  Clock& clock_;
  ClockReading anchor_;
};

}  // namespace rtu
