#pragma once
// The registry of export formats: the files `export -o` writes, chosen by extension.
#include <string>
#include <string_view>

#include "core/format_registry.hpp"
#include "report/pcap_export.hpp"

namespace rtu {

// "pcapng" (the default, first) and "pcap".
const FormatTable<PcapExportFormat>& export_formats();
// The format an output file's name selects (exact case), else pcapng.
const FormatEntry<PcapExportFormat>& export_format_for_path(std::string_view path);
// "Output file: .pcapng or .pcap" for `export -o`.
std::string export_output_help();

}  // namespace rtu
