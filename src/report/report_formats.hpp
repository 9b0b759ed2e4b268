#pragma once
// The registry of report formats: what `report --format` and `live --report-format` accept,
// the report file extensions that choose one, and the writer of each.
#include <string_view>
#include <vector>

#include "core/format_registry.hpp"
#include "core/output_stream.hpp"
#include "report/findings.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {

using ReportWriter = void (*)(OutputStream& out, const TrafficStats& stats,
                              const std::vector<Finding>& findings);

// "text" (the default, first), "json" and "html".
const FormatTable<ReportWriter>& report_formats();
// The format a report file's name selects (exact case: .html/.htm, .json), else text.
const FormatEntry<ReportWriter>& report_format_for_path(std::string_view path);

}  // namespace rtu
