#include "recording_writer.hpp"

#include <memory>
#include <optional>
#include <vector>

#include "capture/byte_output.hpp"
#include "capture/pcap_format.hpp"
#include "capture/pcap_import.hpp"
#include "capture/pcapng_writer.hpp"
#include "capture/rtac_serial.hpp"

namespace rtu::sim {

void write_read_recording(const std::string& path, const LineSettings& line, Nanos resolution,
                          std::span<const WireByte> bytes, std::span<const OutputChunk> chunks) {
  PcapngWriter writer(std::make_unique<FileOutput>(path));
  // Declared as a live recording declares them, so a replay takes them from the file.
  const std::uint32_t interface =
      writer.add_interface({pcap::kLinkTypeRtacSerial, "rtusim",
                            recording_description(line, "rtusim", resolution, std::nullopt), 9, 0});
  std::vector<std::uint8_t> read;
  std::vector<std::uint8_t> record;
  for (const OutputChunk& chunk : chunks) {
    read.clear();
    for (std::size_t i = chunk.first; i < chunk.first + chunk.count; ++i) {
      read.push_back(bytes[i].value);
    }
    build_rtac_record(chunk.t, RtacEvent::kDataRxStart, 0, read, record);
    writer.write_packet(interface, chunk.t, record);
  }
  writer.flush();
}

}  // namespace rtu::sim
