#include "capture/pcap_capture_reader.hpp"

namespace rtu {

PcapCaptureReader::PcapCaptureReader(const CaptureFile& file) : importer_(file) {}

bool PcapCaptureReader::read(CaptureConsumer& to) {
  if (!importer_.next(item_)) return false;
  if (precision_ == 0 || item_.resolution < precision_) precision_ = item_.resolution;
  switch (item_.kind) {
    case PcapItem::Kind::kChunk: to.on_chunk(item_.chunk); break;
    case PcapItem::Kind::kFrame: to.on_frame(item_.bytes, item_.t_start, item_.offset); break;
    case PcapItem::Kind::kNoise: to.on_noise(item_.bytes, item_.t_start, item_.offset); break;
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
