#include "app/run_report.hpp"

#include <fmt/format.h>

#include "core/issue.hpp"
#include "report/report_writers.hpp"

namespace rtu::app {

RunReport::RunReport(DeviceSetup& devices)
    : devices_(devices), stats_(&devices.table), identifier_(devices.library) {
  fanout_.add(stats_);
  fanout_.add(identifier_);
}

void RunReport::finish() {
  devices_.table.assign_identified(identifier_.ranking());  // configured slaves keep theirs
  findings_ = find_problems(stats_);
}

std::string report_format_for(const std::string& path) {
  const auto ends_with = [&](std::string_view suffix) {
    return path.size() >= suffix.size() &&
           path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends_with(".html") || ends_with(".htm")) return "html";
  if (ends_with(".json")) return "json";
  return "text";
}

void RunReport::write(OutputStream& out, const std::string& format) const {
  if (format == "json") {
    write_report_json(out, stats_, findings_);
  } else if (format == "html") {
    write_report_html(out, stats_, findings_);
  } else {
    write_report_text(out, stats_, findings_);
  }
  out.flush();
}

void RunReport::print_findings(std::FILE* out, std::size_t limit) const {
  if (findings_.empty()) {
    fmt::print(out, "rtuscope: findings: none\n");
    return;
  }
  for (std::size_t i = 0; i < findings_.size() && i < limit; ++i) {
    const Finding& f = findings_[i];
    fmt::print(out, "rtuscope: finding {}. [{}] {}\n", i + 1, severity_name(f.severity), f.summary);
    fmt::print(out, "          likely cause: {}\n", f.cause);
  }
  if (findings_.size() > limit) {
    fmt::print(out, "rtuscope: ... {} more findings in the full report (--report FILE)\n",
               findings_.size() - limit);
  }
}

}  // namespace rtu::app
