#pragma once
// Base of the readers whose captures hold only chunks (text hex, Saleae CSV): they produce
// one chunk at a time with next(), and deliver it as a CaptureReader.
#include "capture/capture_reader.hpp"
#include "core/chunk.hpp"

namespace rtu {

class ChunkSource : public CaptureReader {
 public:
  // Fills `out` with the next chunk; its spans stay valid until the next call.
  // Returns false at the end. Throws InputError on unusable input (with file:line).
  virtual bool next(Chunk& out) = 0;

  bool read(CaptureConsumer& to) final {
    if (!next(chunk_)) return false;
    to.on_chunk(chunk_);
    return true;
  }

 private:
  Chunk chunk_;
};

}  // namespace rtu
