#pragma once
// What a replay's decoding pass does with each item a capture reader delivers: raw reads
// or frame records into the decode pipeline (see replay.hpp for which), in order.
#include <cstdint>
#include <functional>
#include <span>

#include "capture/capture_reader.hpp"
#include "pipeline/decode_pipeline.hpp"

namespace rtu {

class CaptureFeed final : public CaptureConsumer {
 public:
  // `use_chunks`: raw reads are re-framed and frame records left aside, else the reverse.
  // `on_chunk` (may be empty) sees each raw read just before the pipeline does.
  CaptureFeed(DecodePipeline& pipeline, bool use_chunks, Nanos char_time,
              std::function<void(const Chunk&)> on_chunk = {});

  void on_chunk(const Chunk& chunk) override;
  void on_byte_reads(const ByteReads& reads) override;
  void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) override;
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) override;
  // A live recording ends where the live run stopped: what was pending then (a request
  // still waiting for its answer) is decided as live decided it. Items after it (the next
  // file of a rotation set, from a recorder started again) come after a break.
  void on_end(Nanos t) override {
    ++items_;
    pipeline_.idle(t);
    ended_ = true;
  }
  // Items delivered so far, each read of a run counted (for progress).
  [[nodiscard]] std::uint64_t items() const { return items_; }

 private:
  [[nodiscard]] Nanos t_end(std::span<const std::uint8_t> bytes, Nanos t_start) const {
    return t_start + static_cast<Nanos>(bytes.size()) * char_time_;
  }
  [[nodiscard]] Nanos on_free_line(Nanos t_start) const;
  // Before an item: after an end, the capture broke (see on_end()).
  void after_end() {
    if (!ended_) return;
    ended_ = false;
    pipeline_.break_capture();
    line_free_at_ = kUnknownTime;
  }

  DecodePipeline& pipeline_;
  bool use_chunks_;
  Nanos char_time_;
  std::function<void(const Chunk&)> on_chunk_;
  Nanos line_free_at_ = kUnknownTime;
  std::uint64_t items_ = 0;
  bool ended_ = false;  // an end came, and no item since
};

}  // namespace rtu
