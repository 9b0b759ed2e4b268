#include "capture/capture_formats.hpp"

#include <utility>

#include "capture/pcap_capture_reader.hpp"
#include "capture/saleae_reader.hpp"
#include "capture/text_hex_reader.hpp"

namespace rtu {
namespace {

std::unique_ptr<CaptureReader> open_text_hex(const CaptureFile& file, WarningSink warnings) {
  return std::make_unique<TextHexReader>(file, std::move(warnings));
}

std::unique_ptr<CaptureReader> open_saleae(const CaptureFile& file, WarningSink warnings) {
  return std::make_unique<SaleaeReader>(file, std::move(warnings));
}

std::unique_ptr<CaptureReader> open_pcap(const CaptureFile& file, WarningSink warnings) {
  return std::make_unique<PcapCaptureReader>(file, std::move(warnings));
}

}  // namespace

const FormatTable<CaptureReaderFactory>& capture_formats() {
  static const FormatTable<CaptureReaderFactory> kFormats = {
      {"hex", "text hex (.hex/.txt)", {".hex", ".txt"}, {CaptureFormat::kTextHex, open_text_hex}},
      {"saleae", "Saleae CSV", {".csv"}, {CaptureFormat::kSaleaeCsv, open_saleae}},
      {"pcap", "pcap/pcapng", {".pcap", ".pcapng", ".cap"}, {CaptureFormat::kPcap, open_pcap}},
  };
  return kFormats;
}

const CaptureFormatEntry& capture_format(CaptureFormat format) {
  for (const auto& entry : capture_formats()) {
    if (entry.factory.format == format) return entry;
  }
  return capture_formats().front();  // unreachable: every CaptureFormat has an entry
}

const CaptureFormatEntry* capture_format_for_path(const std::string& path) {
  return find_format_for_path(capture_formats(), path, ExtensionCase::kAnyCase);
}

std::string capture_file_help() {
  std::string help = "Capture: ";
  for (const auto& entry : capture_formats()) {
    if (&entry != &capture_formats().front()) help += ", ";
    help += entry.description;
  }
  return help;
}

}  // namespace rtu
