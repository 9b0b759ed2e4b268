#pragma once
// Classic pcap writer (one link type per file, µs or ns timestamps). Each record (header
// and data) goes to the ByteOutput in one write(), like PcapngWriter's blocks.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "capture/byte_order.hpp"
#include "capture/byte_output.hpp"
#include "core/time.hpp"

namespace rtu {

enum class PcapResolution : std::uint8_t { kMicros, kNanos };

class PcapWriter {
 public:
  // Writes the 24-byte global header at once.
  PcapWriter(std::unique_ptr<ByteOutput> output, std::uint16_t link_type,
             PcapResolution resolution = PcapResolution::kNanos,
             ByteOrder order = host_byte_order(), std::uint32_t snap_length = 65535);

  // `t` in ns since 1970-01-01 UTC, truncated to the file's resolution. Throws InputError
  // for times before 1970 or after 2106 (the 32-bit seconds field).
  void write_packet(Nanos t, std::span<const std::uint8_t> data, std::uint32_t original_length = 0);

  void flush() { output_->flush(); }
  [[nodiscard]] ByteOutput& output() { return *output_; }

 private:
  std::unique_ptr<ByteOutput> output_;
  PcapResolution resolution_;
  ByteOrder order_;
  std::vector<std::uint8_t> record_;
};

}  // namespace rtu
