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

 protected:
  // For read_many(), from a reader that can produce one-byte reads for less than a next()
  // each: the reads that come next, up to `room` of them, as long as each is one byte (no
  // line error, no start time, port 0) from the origin after the one before, the first from
  // `first_origin`; their bytes and end times go to `bytes` and `t_ends`. Returns how many;
  // 0 (the default) leaves the next read to next(). Throws as next() does.
  virtual std::size_t next_byte_reads(std::uint8_t* bytes, Nanos* t_ends, std::size_t room,
                                      std::uint64_t& first_origin) {
    (void)bytes, (void)t_ends, (void)room, (void)first_origin;
    return 0;
  }

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
