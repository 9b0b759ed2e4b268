#include "report/export_formats.hpp"

namespace rtu {

const FormatTable<PcapExportFormat>& export_formats() {
  static const FormatTable<PcapExportFormat> kFormats = {
      {"pcapng", "", {".pcapng"}, PcapExportFormat::kPcapng},
      {"pcap", "", {".pcap"}, PcapExportFormat::kPcap},
  };
  return kFormats;
}

const FormatEntry<PcapExportFormat>& export_format_for_path(std::string_view path) {
  const auto* entry = find_format_for_path(export_formats(), path, ExtensionCase::kExact);
  return entry != nullptr ? *entry : export_formats().front();
}

std::string export_output_help() {
  std::string help = "Output file: ";
  for (const auto& entry : export_formats()) {
    if (&entry != &export_formats().front()) help += " or ";
    help += entry.extensions.front();
  }
  return help;
}

}  // namespace rtu
