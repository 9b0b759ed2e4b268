#include "capture/pcap_capture_reader.hpp"

#include <utility>

namespace rtu {

PcapCaptureReader::PcapCaptureReader(const CaptureFile& file, WarningSink warnings)
    : importer_(file), warnings_(std::move(warnings)), record_clamp_(importer_.name(), warnings_) {}

BackwardTimeClamp& PcapCaptureReader::chunk_clamp(std::uint8_t port) {
  while (chunk_clamps_.size() <= port) chunk_clamps_.emplace_back(importer_.name(), warnings_);
  return chunk_clamps_[port];
}

bool PcapCaptureReader::read(CaptureConsumer& to) {
  if (!importer_.next(item_)) {
    record_clamp_.finish();
    for (auto& clamp : chunk_clamps_) clamp.finish();
    return false;
  }
  if (precision_ == 0 || item_.resolution < precision_) precision_ = item_.resolution;
  switch (item_.kind) {
    case PcapItem::Kind::kChunk: {
      const Nanos t_end = item_.chunk.t_end;
      item_.chunk.t_end = chunk_clamp(item_.chunk.port).admit_at_offset(t_end, item_.offset);
      // Clamped here, or marked so by whoever wrote the file (a raw export of a clamped read).
      item_.chunk.time_clamped = item_.chunk.time_clamped || item_.chunk.t_end != t_end;
      to.on_chunk(item_.chunk);
      break;
    }
    case PcapItem::Kind::kFrame:
      item_.t_start = record_clamp_.admit_at_offset(item_.t_start, item_.offset);
      to.on_frame(item_.bytes, item_.t_start, item_.offset);
      break;
    case PcapItem::Kind::kNoise:
      item_.t_start = record_clamp_.admit_at_offset(item_.t_start, item_.offset);
      to.on_noise(item_.bytes, item_.t_start, item_.offset);
      break;
    case PcapItem::Kind::kEnd: to.on_end(item_.t_start); break;
  }
  return true;
}

std::vector<std::string> PcapCaptureReader::capture_warnings() const {
  std::string cut = cut_records_warning(importer_.name(), importer_.cut_records());
  if (cut.empty()) return {};
  return {std::move(cut)};
}

}  // namespace rtu
