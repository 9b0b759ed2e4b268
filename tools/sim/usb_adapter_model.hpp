#pragma once
// How a host sees the wire: one read per byte (a logic analyser or an ideal UART), or the
// reads a USB-serial adapter of the FTDI kind produces. Each output chunk is a run of
// consecutive wire bytes and the time the host's read() returned them.
#include <cstddef>
#include <span>
#include <vector>

#include "core/time.hpp"
#include "rng.hpp"
#include "timeline.hpp"

namespace rtu::sim {

struct OutputChunk {
  Nanos t = 0;            // when the last byte became available to the host
  std::size_t first = 0;  // index of the first byte in the timeline
  std::size_t count = 0;
};

// One chunk per byte, stamped with the byte's exact end.
std::vector<OutputChunk> chunk_per_byte(std::span<const WireByte> bytes);

// The FTDI model (see the facts sheet on FTDI chunking):
// - the chip collects received bytes; it sends a USB packet when `packet` data bytes are
//   waiting (62 at full speed), or when its latency timer expires with data waiting;
//   the latency timer restarts whenever a packet is sent, and runs freely otherwise;
// - the host collects a packet at the next USB frame (every `usb_frame`);
// - the reading thread wakes up 0..`jitter` later and read() returns everything that has
//   arrived by then, so a late wake-up merges packets into one chunk.
// Chunk times are strictly increasing and never precede the end of the chunk's last byte.
//
// With `idle_flush` > 0, the chip is of the kind that sends what it holds once the line has
// been idle that long (CH34x, CP210x, PL2303 as commonly described, and a 16550 UART's
// character timeout of about 4 character times): no latency timer; a packet still goes out
// when `packet` data bytes are waiting. A frame then comes a read at a time, unless the
// silence after it is shorter than `idle_flush`.
struct UsbAdapterModel {
  Nanos latency = 16 * kNanosPerMilli;
  std::size_t packet = 62;
  Nanos jitter = 2 * kNanosPerMilli;
  Nanos usb_frame = 1 * kNanosPerMilli;
  Nanos idle_flush = 0;
};

std::vector<OutputChunk> chunk_usb(std::span<const WireByte> bytes, const UsbAdapterModel& model,
                                   Rng rng);

}  // namespace rtu::sim
