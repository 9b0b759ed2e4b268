#pragma once
// A CaptureConsumer for reader tests: every call it gets, written as one line of text, so two
// ways of reading a capture can be compared line by line. A run of one-byte reads is written
// read by read, as on_chunk() writes each, and counted.
#include <fmt/format.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "capture/capture_reader.hpp"

namespace rtu::testing {

class ItemTranscript : public CaptureConsumer {
 public:
  void on_chunk(const Chunk& c) override {
    lines.push_back(fmt::format("chunk t={} first={} port={} origin={} bytes={:02x} errors={:02x}",
                                c.t_end, c.t_first_start, c.port, c.origin, fmt::join(c.bytes, ""),
                                fmt::join(c.errors, "")));
  }
  void on_byte_reads(const ByteReads& reads) override {
    ++runs;
    reads_in_runs += reads.size();
    CaptureConsumer::on_byte_reads(reads);
  }
  void on_frame(std::span<const std::uint8_t> adu, Nanos t, std::uint64_t origin) override {
    lines.push_back(fmt::format("frame t={} origin={} {:02x}", t, origin, fmt::join(adu, "")));
  }
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t, std::uint64_t origin) override {
    lines.push_back(fmt::format("noise t={} origin={} {:02x}", t, origin, fmt::join(bytes, "")));
  }
  void on_end(Nanos t) override { lines.push_back(fmt::format("end t={}", t)); }

  std::vector<std::string> lines;
  std::size_t runs = 0;           // on_byte_reads() calls
  std::size_t reads_in_runs = 0;  // the reads they held
};

}  // namespace rtu::testing
