#pragma once
// Base of the readers whose captures hold only chunks (text hex, Saleae CSV): they produce
// one chunk at a time with next(), and deliver it as a CaptureReader.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "capture/capture_reader.hpp"
#include "core/chunk.hpp"

namespace rtu {

class ChunkSource : public CaptureReader {
 public:
  // Fills `out` with the next chunk; its spans stay valid until the next call.
  // Returns false at the end. Throws InputError on unusable input (with file:line).
  virtual bool next(Chunk& out) = 0;

  bool read(CaptureConsumer& to) final {
    if (at_end_ || !next(chunk_)) return false;
    to.on_chunk(chunk_);
    return true;
  }
  // Gathers one-byte reads that follow one another (one port, no line error, no start time,
  // consecutive origins) into runs, each delivered as one on_byte_reads(); any other chunk
  // is delivered as it comes. Ends after the first chunk that is not a one-byte read, or
  // after `max_reads` reads, or at the end or the damage.
  bool read_many(CaptureConsumer& to, std::size_t max_reads) final;

 private:
  Chunk chunk_;
  bool at_end_ = false;  // next() said so during read_many(), after a run was delivered
  // The run being gathered by read_many(): kMaxRun reads at most, as the bytes and end times
  // of ByteReads.
  static constexpr std::size_t kMaxRun = 4096;
  std::unique_ptr<std::uint8_t[]> run_bytes_;
  std::unique_ptr<Nanos[]> run_times_;
};

}  // namespace rtu
