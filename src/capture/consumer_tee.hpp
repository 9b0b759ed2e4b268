#pragma once
// Hands each item a reader delivers to two consumers, `first` then `then`. They must not
// depend on each other: a run of reads goes to one whole before the other.
#include <cstdint>
#include <span>

#include "capture/capture_reader.hpp"

namespace rtu {

class ConsumerTee final : public CaptureConsumer {
 public:
  ConsumerTee(CaptureConsumer& first, CaptureConsumer& then) : first_(first), then_(then) {}
  void on_chunk(const Chunk& chunk) override {
    first_.on_chunk(chunk);
    then_.on_chunk(chunk);
  }
  // A run goes to `first` whole, then to `then`: each sees every read in order, one
  // consumer's reads are not interleaved with the other's.
  void on_byte_reads(const ByteReads& reads) override {
    first_.on_byte_reads(reads);
    then_.on_byte_reads(reads);
  }
  void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) override {
    first_.on_frame(adu, t_start, origin);
    then_.on_frame(adu, t_start, origin);
  }
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) override {
    first_.on_noise(bytes, t_start, origin);
    then_.on_noise(bytes, t_start, origin);
  }
  void on_end(Nanos t) override {
    first_.on_end(t);
    then_.on_end(t);
  }

 private:
  CaptureConsumer& first_;
  CaptureConsumer& then_;
};

}  // namespace rtu
