#include "capture/pcap_writer.hpp"

#include <fmt/format.h>

#include "capture/pcap_format.hpp"
#include "core/input_error.hpp"

namespace rtu {

PcapWriter::PcapWriter(std::unique_ptr<ByteOutput> output, std::uint16_t link_type,
                       PcapResolution resolution, ByteOrder order, std::uint32_t snap_length)
    : output_(std::move(output)), resolution_(resolution), order_(order) {
  std::vector<std::uint8_t> header;
  append<std::uint32_t>(
      header, resolution == PcapResolution::kNanos ? pcap::kMagicNanos : pcap::kMagicMicros,
      order_);
  append<std::uint16_t>(header, 2, order_);
  append<std::uint16_t>(header, 4, order_);
  append<std::uint32_t>(header, 0, order_);  // thiszone
  append<std::uint32_t>(header, 0, order_);  // sigfigs
  append<std::uint32_t>(header, snap_length, order_);
  append<std::uint32_t>(header, link_type, order_);
  output_->write(header);
}

void PcapWriter::write_packet(Nanos t, std::span<const std::uint8_t> data,
                              std::uint32_t original_length) {
  const Nanos seconds = t / kNanosPerSecond;
  if (t < 0 || seconds > 0xFFFFFFFFLL) {
    throw InputError(fmt::format(
        "timestamp {:.9f} s is outside 1970..2106; classic pcap cannot hold it", to_seconds(t)));
  }
  const Nanos fraction = t % kNanosPerSecond;
  const auto captured = static_cast<std::uint32_t>(data.size());
  record_.clear();
  append<std::uint32_t>(record_, static_cast<std::uint32_t>(seconds), order_);
  append<std::uint32_t>(record_,
                        static_cast<std::uint32_t>(
                            resolution_ == PcapResolution::kNanos ? fraction : fraction / 1000),
                        order_);
  append<std::uint32_t>(record_, captured, order_);
  append<std::uint32_t>(record_, original_length > captured ? original_length : captured, order_);
  record_.insert(record_.end(), data.begin(), data.end());
  output_->write(record_);
}

}  // namespace rtu
