#pragma once
// The report of a capture taken live (`rtuscope live --report`, `rtuscope demo`): statistics
// gathered while the records pass by, with the same device points as `rtuscope report`.
// Slaves no option names are identified from the traffic seen during the run, so their
// models are known by the time the report is written (their values are named from then on:
// a live run cannot look ahead).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/device_options.hpp"
#include "core/output_stream.hpp"
#include "dissect/map_identifier.hpp"
#include "pipeline/record_fanout.hpp"
#include "report/findings.hpp"
#include "report/traffic_stats.hpp"

namespace rtu::app {

class RunReport {
 public:
  // `devices` must outlive the report; its table is the one the run's device stage uses.
  explicit RunReport(DeviceSetup& devices);

  // Where the run's records go, after a device stage that collects values (statistics and
  // identification).
  [[nodiscard]] RecordSink& sink() { return fanout_; }

  // Identifies unnamed slaves and ranks the findings; call once, after the run stopped.
  // `resolution_at_end`: the one the reads showed by then (LiveSummary::timing_resolution),
  // what the report judges observability by, as `rtuscope report` of the run's recording does.
  void finish(Nanos resolution_at_end);
  [[nodiscard]] const std::vector<Finding>& findings() const { return findings_; }
  // The statistics gathered so far (what the metrics render between two records).
  [[nodiscard]] const TrafficStats& stats() const { return stats_; }

  // Writes the whole report as `format` ("text", "json" or "html").
  void write(OutputStream& out, const std::string& format) const;
  // The `limit` most important findings, one line each (for the end of a run on screen).
  void print_findings(std::FILE* out, std::size_t limit) const;

 private:
  DeviceSetup& devices_;
  TrafficStats stats_;
  dissect::MapIdentifier identifier_;
  RecordFanout fanout_;
  std::vector<Finding> findings_;
};

// "html", "json" or "text" for a report file name.
std::string report_format_for(const std::string& path);

}  // namespace rtu::app
