#pragma once
// Any capture as chunks only, for consumers that take nothing else: chunks as they are, and
// each frame or noise record as one chunk whose first byte starts at the record's time and
// which lasts its length in character times (so a framer sees the same boundaries). The
// capture's end is skipped.
#include "capture/capture_reader.hpp"
#include "core/chunk.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

class ChunkView {
 public:
  // `line`: for the character time when the capture declares no settings.
  explicit ChunkView(CaptureReader& reader, LineSettings line = {});
  // Fills `out` with the next chunk (spans valid until the next call); false at the end.
  bool next(Chunk& out);

 private:
  CaptureReader& reader_;
  LineSettings line_;
};

}  // namespace rtu
