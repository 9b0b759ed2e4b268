#include "pipeline/capture_feed.hpp"

#include <utility>

namespace rtu {

CaptureFeed::CaptureFeed(DecodePipeline& pipeline, bool use_chunks, Nanos char_time,
                         std::function<void(const Chunk&)> on_chunk)
    : pipeline_(pipeline),
      use_chunks_(use_chunks),
      char_time_(char_time),
      on_chunk_(std::move(on_chunk)) {}

void CaptureFeed::on_chunk(const Chunk& chunk) {
  ++items_;
  after_end();
  if (!use_chunks_) return;
  if (on_chunk_) on_chunk_(chunk);
  pipeline_.push(chunk);
}

void CaptureFeed::on_byte_reads(const ByteReads& reads) {
  after_end();
  if (!use_chunks_ || on_chunk_) {
    CaptureConsumer::on_byte_reads(reads);  // each read seen on its own
    return;
  }
  items_ += reads.size();
  pipeline_.push_byte_reads(reads);
}

void CaptureFeed::on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) {
  ++items_;
  after_end();
  if (use_chunks_) return;
  t_start = on_free_line(t_start);
  line_free_at_ = t_end(adu, t_start);
  pipeline_.push_frame(adu, t_start, line_free_at_, origin);
}

void CaptureFeed::on_noise(std::span<const std::uint8_t> bytes, Nanos t_start,
                           std::uint64_t origin) {
  ++items_;
  after_end();
  if (use_chunks_) return;
  t_start = on_free_line(t_start);
  line_free_at_ = t_end(bytes, t_start);
  pipeline_.push_noise(bytes, t_start, line_free_at_, origin);
}

// One line carries one record at a time: a record stamped before the previous one ended (its
// time went backwards and was clamped by the reader, or another tool stamped it late) starts
// when the line was free, so no latency or gap comes out negative.
Nanos CaptureFeed::on_free_line(Nanos t_start) const {
  return line_free_at_ != kUnknownTime && t_start < line_free_at_ ? line_free_at_ : t_start;
}

}  // namespace rtu
