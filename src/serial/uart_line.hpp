#pragma once
// A UART line at the bit level, with no clock: what a transmitter at one setting puts on
// the wire, and what a receiver at another setting makes of it. The virtual bus uses it to
// be wrong the way a real bus is (wrong baud, wrong parity, swapped A/B).
//
// Character format: start bit 0, 8 data bits LSB first, optional parity, 1 or 2 stop bits
// at 1; the idle line is 1 (0 when the pair is swapped and every level is inverted).
//
// Times are integer picoseconds on a timeline the caller chooses; bit boundaries are
// computed from the character's start (never accumulated), so there is no drift.
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "serial/line_settings.hpp"

namespace rtu {

using Picos = std::int64_t;
inline constexpr Picos kPicosPerSecond = 1'000'000'000'000;

// Offset of `half_bits` half bit times at `baud` (so 2 is one whole bit).
[[nodiscard]] Picos half_bits_at(std::uint32_t baud, std::int64_t half_bits);
// Length of one character on the wire, stop bits included.
[[nodiscard]] Picos char_duration(const LineSettings& line);

// The level of the line over time: piecewise constant, changes appended in time order.
class LineLevels {
 public:
  explicit LineLevels(bool idle_level = true) : initial_(idle_level) {}

  // The line is at `level` from `t` on. `t` must not be before the last change.
  void set(Picos t, bool level);
  [[nodiscard]] bool level_at(Picos t) const;
  // The first fall from 1 to 0 at or after `from` (a line already low at `from` must rise
  // first). nullopt when none is on the line yet.
  [[nodiscard]] std::optional<Picos> falling_edge_from(Picos from) const;
  // Drops the changes before `t`, keeping the level at `t` (bounded memory).
  void forget_before(Picos t);

 private:
  bool initial_;                                 // the level before the first change
  std::vector<std::pair<Picos, bool>> changes_;  // (time, level from then on)
};

// Draws `byte` as one character from `start` at the transmitter's settings; every level
// is inverted when `inverted` (A and B swapped). Returns the end of its last stop bit,
// where the line is left at idle.
Picos render_char(LineLevels& line, Picos start, std::uint8_t byte, const LineSettings& tx,
                  bool inverted = false);

struct ReceivedChar {
  std::uint8_t byte = 0;
  std::uint8_t error = 0;  // LineError bits (core/chunk.hpp): parity, framing, break
  Picos start = 0;         // the falling edge it was started by
  Picos end = 0;           // nominal end of its (first) stop bit
};

// A UART receiver: it waits for a falling edge, checks the start bit at its middle (a
// shorter low pulse is a false start and ignored), then samples data, parity and the first
// stop bit at the centres of its own bit times. Like common UARTs (16550 and kin) it
// checks only the first stop bit, so 8N1 and 8N2 receive alike.
//   stop bit 0            → framing error
//   every bit 0, stop too → break (a 00 byte flagged kBreak)
//   wrong parity          → parity error
// After a character it looks for the next falling edge from its stop bit's sample point.
class UartReceiver {
 public:
  explicit UartReceiver(const LineSettings& rx, Picos from = 0) : rx_(rx), resume_(from) {}

  // Appends every character whose samples all lie before `known_until`.
  void receive(const LineLevels& line, Picos known_until, std::vector<ReceivedChar>& out);
  // When the character the line has already started will have been sampled; nullopt when
  // no start is waiting.
  [[nodiscard]] std::optional<Picos> next_complete(const LineLevels& line) const;
  // New settings from `from` on (a program reconfigured its port).
  void reconfigure(const LineSettings& rx, Picos from);
  [[nodiscard]] const LineSettings& settings() const { return rx_; }
  [[nodiscard]] Picos resume_point() const { return resume_; }

 private:
  // Sample offset of the first stop bit, from the start edge.
  [[nodiscard]] Picos stop_sample_offset() const;

  LineSettings rx_;
  Picos resume_;
};

// Transmits `bytes` back to back from `start` and receives them: the whole round trip on
// an otherwise idle line. For tests and for reasoning about a setting.
std::vector<ReceivedChar> transmit_and_receive(const std::vector<std::uint8_t>& bytes,
                                               const LineSettings& tx, const LineSettings& rx,
                                               bool inverted = false);

}  // namespace rtu
