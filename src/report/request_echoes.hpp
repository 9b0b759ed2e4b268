#pragma once
// Requests seen twice in a row: the same bytes again, with no frame between, starting less
// than t3.5 (plus what the timestamps blur) after the first copy ended. No master repeats a
// request that fast (a retry waits for its response timeout), but an RS-485 adapter that
// hears its own transmission does, and so does a capture of one port's transmit and receive
// lines together. The tracker reads the copy as a new request, so the first copy of each
// pair counts as unanswered: the report must say where those timeouts come from.
#include <array>
#include <cstdint>

#include "framing/record.hpp"

namespace rtu {

class RequestEchoes {
 public:
  // `window`: the longest silence between the copies (t3.5 plus the timing resolution).
  void set_window(Nanos window) { window_ = window; }

  // Each frame in order; `is_request` as the tracker read it.
  void on_frame(const Record& frame, bool is_request);

  [[nodiscard]] std::uint64_t echoes() const { return echoes_; }
  // First copies the tracker called timed out (because the copy followed as a request).
  [[nodiscard]] std::uint64_t timeouts_on_first_copies() const { return timeouts_; }
  [[nodiscard]] Nanos longest_gap() const { return longest_gap_; }  // 0 when none

 private:
  Nanos window_ = 0;
  std::array<std::uint8_t, kMaxAdu> last_{};
  std::uint16_t last_size_ = 0;  // 0: the last frame was no request (or was a copy)
  Nanos last_end_ = kUnknownTime;
  bool last_timed_out_ = false;
  std::uint64_t echoes_ = 0;
  std::uint64_t timeouts_ = 0;
  Nanos longest_gap_ = 0;
};

}  // namespace rtu
