#include "serial/clock.hpp"

#include <time.h>

namespace rtu {
namespace {

Nanos read_clock(clockid_t id) {
  timespec ts{};
  ::clock_gettime(id, &ts);
  return static_cast<Nanos>(ts.tv_sec) * kNanosPerSecond + static_cast<Nanos>(ts.tv_nsec);
}

}  // namespace

ClockReading SystemClock::now() {
  ClockReading r;
  r.monotonic = read_clock(CLOCK_MONOTONIC);
  r.wall = read_clock(CLOCK_REALTIME);
  return r;
}

CaptureClock::CaptureClock(Clock& clock) : clock_(clock), anchor_(clock.now()) {}

Nanos CaptureClock::now() {
  return at(clock_.now());
}

}  // namespace rtu
