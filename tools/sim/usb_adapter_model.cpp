#include "usb_adapter_model.hpp"

#include <algorithm>

namespace rtu::sim {

std::vector<OutputChunk> chunk_per_byte(std::span<const WireByte> bytes) {
  std::vector<OutputChunk> out;
  out.reserve(bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) out.push_back({bytes[i].end, i, 1});
  return out;
}

namespace {

struct Packet {
  Nanos sent = 0;  // when the chip hands it to the USB
  std::size_t first = 0;
  std::size_t count = 0;
};

// Puts byte `i`, which arrived at `arrive`, into the open packet, and sends the packet once it
// holds `packet` bytes; returns whether it did.
bool add_byte(Packet& open, std::size_t i, Nanos arrive, std::size_t packet,
              std::vector<Packet>& packets) {
  if (open.count == 0) open.first = i;
  ++open.count;
  if (open.count < packet) return false;
  open.sent = arrive;
  packets.push_back(open);
  open.count = 0;
  return true;
}

// The chip side: bytes in, packets out.
std::vector<Packet> ftdi_packets(std::span<const WireByte> bytes, const UsbAdapterModel& m,
                                 Rng& rng) {
  std::vector<Packet> packets;
  if (bytes.empty()) return packets;
  // The timer's phase relative to the traffic is arbitrary.
  Nanos expiry = bytes.front().end + rng.nanos(0, m.latency - 1);
  Packet open{0, 0, 0};
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const Nanos arrive = bytes[i].end;
    if (expiry <= arrive) {
      if (open.count > 0) {
        open.sent = expiry;
        packets.push_back(open);
        open.count = 0;
        expiry += m.latency;
      }
      // An idle timer keeps ticking: skip the expiries that found nothing to send.
      if (expiry <= arrive) expiry += ((arrive - expiry) / m.latency + 1) * m.latency;
    }
    if (add_byte(open, i, arrive, m.packet, packets)) expiry = arrive + m.latency;
  }
  if (open.count > 0) {
    open.sent = expiry;
    packets.push_back(open);
  }
  return packets;
}

// The chip side of an adapter that sends when the line goes idle: bytes in, packets out.
std::vector<Packet> idle_flush_packets(std::span<const WireByte> bytes, const UsbAdapterModel& m) {
  std::vector<Packet> packets;
  Packet open{0, 0, 0};
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    // The line was idle from the last byte's end to this one's start.
    if (open.count > 0 && bytes[i].start - bytes[i - 1].end > m.idle_flush) {
      open.sent = bytes[i - 1].end + m.idle_flush;
      packets.push_back(open);
      open.count = 0;
    }
    add_byte(open, i, bytes[i].end, m.packet, packets);
  }
  if (open.count > 0) {
    open.sent = bytes.back().end + m.idle_flush;
    packets.push_back(open);
  }
  return packets;
}

}  // namespace

std::vector<OutputChunk> chunk_usb(std::span<const WireByte> bytes, const UsbAdapterModel& m,
                                   Rng rng) {
  const std::vector<Packet> packets =
      m.idle_flush > 0 ? idle_flush_packets(bytes, m) : ftdi_packets(bytes, m, rng);
  const Nanos frame_phase = rng.nanos(0, m.usb_frame - 1);
  // A packet reaches the host at the first USB frame boundary not before it was sent.
  const auto at_host = [&](const Packet& p) {
    const Nanos since = p.sent - frame_phase;
    const Nanos frames = since <= 0 ? 0 : (since + m.usb_frame - 1) / m.usb_frame;
    return frame_phase + frames * m.usb_frame;
  };
  std::vector<OutputChunk> out;
  std::size_t k = 0;
  while (k < packets.size()) {
    const Nanos wake = at_host(packets[k]) + rng.nanos(0, m.jitter);
    OutputChunk chunk{wake, packets[k].first, packets[k].count};
    ++k;
    while (k < packets.size() && at_host(packets[k]) <= wake) {
      chunk.count += packets[k].count;
      ++k;
    }
    // Chunk times strictly increase: a wake-up never precedes the previous one.
    if (!out.empty()) chunk.t = std::max(chunk.t, out.back().t + 1);
    out.push_back(chunk);
  }
  return out;
}

}  // namespace rtu::sim
