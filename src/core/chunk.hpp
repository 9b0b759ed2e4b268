#pragma once
// The unit every capture source produces: the bytes one read() returned, stamped with the
// time the read completed, which is when the LAST byte had finished arriving.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/time.hpp"

namespace rtu {

// Per-byte line conditions, as a bit mask. A source that cannot see them leaves 0.
enum LineError : std::uint8_t {
  kLineOk = 0,
  kParityError = 1U << 0U,
  kFramingError = 1U << 1U,
  kBreak = 1U << 2U,
  kOverrun = 1U << 3U,
};

struct Chunk {
  Nanos t_end = 0;  // end of the last byte, on the input's clock
  // Exact start of the first byte when the source measured it (logic analysers);
  // kUnknownTime when only the read completion is known.
  Nanos t_first_start = kUnknownTime;
  std::span<const std::uint8_t> bytes;
  std::span<const std::uint8_t> errors;  // LineError per byte, or empty when none
  std::uint64_t origin = 0;  // where it came from in the input (line number or byte offset)
  // Which receiver read it: 0, or 1 for the second port of a two-port capture (the two
  // directions of a link). Each port is framed on its own.
  std::uint8_t port = 0;
  // The input's time went back here and the reader clamped it to the time before (an NTP
  // step in a logger, a writer stamping from two threads): the read came after the one
  // before, but how long after is not known, so the silence before it is not evidence.
  bool time_clamped = false;
  // The host read this later than its bytes arrived, by more than the timing resolution
  // allows for (the reading thread was busy, or waited for a CPU: live capture measures
  // both). How much of that delay came after the last byte is not known, so the read's
  // time is no evidence of the silence before it, nor of the one after it.
  bool read_late = false;
  // For a late read: the latest moment, on the input's clock, its port was seen holding no
  // unread bytes (its bytes came after it), so the line is known quiet up to then as far as
  // an adapter's delivery delay allows; kUnknownTime where that is not known.
  Nanos quiet_until = kUnknownTime;
};

// One-byte reads in a row on one port, none with a line error or a measured start: what a
// per-byte capture holds, handed on as one run instead of a call per byte. Read i is
// bytes[i], completed at t_ends[i], from origin + i in the input.
struct ByteReads {
  std::span<const std::uint8_t> bytes;
  const Nanos* t_ends = nullptr;  // bytes.size() of them
  std::uint64_t origin = 0;
  std::uint8_t port = 0;

  // Whether `chunk` is a read such a run holds (one byte, no line error, no start time, a
  // time as the input gave it, read in time).
  [[nodiscard]] static bool holds(const Chunk& chunk) {
    return chunk.bytes.size() == 1 && chunk.errors.empty() && chunk.t_first_start == kUnknownTime &&
           !chunk.time_clamped && !chunk.read_late;
  }
  [[nodiscard]] std::size_t size() const { return bytes.size(); }
  // Read i as the Chunk it stands for.
  [[nodiscard]] Chunk read(std::size_t i) const {
    Chunk chunk;
    chunk.t_end = t_ends[i];
    chunk.bytes = bytes.subspan(i, 1);
    chunk.origin = origin + i;
    chunk.port = port;
    return chunk;
  }
};

}  // namespace rtu
