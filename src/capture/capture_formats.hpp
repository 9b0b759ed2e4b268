#pragma once
// The registry of capture file formats: what `decode`, `report`, `export` and `identify`
// read, the extensions that select a format when its content says nothing, and its reader.
#include <memory>
#include <string>

#include "capture/capture_file.hpp"
#include "capture/capture_reader.hpp"
#include "capture/capture_warnings.hpp"
#include "core/format_registry.hpp"

namespace rtu {

enum class CaptureFormat : std::uint8_t { kTextHex, kSaleaeCsv, kPcap };

struct CaptureReaderFactory {
  CaptureFormat format;
  std::unique_ptr<CaptureReader> (*open)(const CaptureFile& file, WarningSink warnings);
};

using CaptureFormatEntry = FormatEntry<CaptureReaderFactory>;

// Every format, the default one (text hex) first.
const FormatTable<CaptureReaderFactory>& capture_formats();
const CaptureFormatEntry& capture_format(CaptureFormat format);
// The format an extension selects (any case), or null.
const CaptureFormatEntry* capture_format_for_path(const std::string& path);
// "Capture: text hex (.hex/.txt), Saleae CSV, pcap/pcapng" for a command's file argument.
std::string capture_file_help();

}  // namespace rtu
