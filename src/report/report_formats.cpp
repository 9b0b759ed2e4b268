#include "report/report_formats.hpp"

#include "report/report_writers.hpp"

namespace rtu {

const FormatTable<ReportWriter>& report_formats() {
  static const FormatTable<ReportWriter> kFormats = {
      {"text", "", {}, write_report_text},
      {"json", "", {".json"}, write_report_json},
      {"html", "", {".html", ".htm"}, write_report_html},
  };
  return kFormats;
}

const FormatEntry<ReportWriter>& report_format_for_path(std::string_view path) {
  const auto* entry = find_format_for_path(report_formats(), path, ExtensionCase::kExact);
  return entry != nullptr ? *entry : report_formats().front();
}

}  // namespace rtu
