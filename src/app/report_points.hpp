#pragma once
// The register values a report shows, wired from the device options: slaves that --device
// or --bus names decode with their maps; slaves nobody names get the map the MapIdentifier
// is confident about (when the caller can show it the traffic first); every other slave
// keeps raw registers. One function, so `report` and the end-of-run report of a live
// capture build it the same way.
#include <functional>
#include <memory>

#include "app/device_options.hpp"
#include "dissect/device_point_source.hpp"
#include "pipeline/replay.hpp"
#include "report/raw_register_source.hpp"

namespace rtu::app {

// Owns the maps and both sources (the device source points at the raw one and into the
// library, hence not movable).
struct ReportPoints {
  std::unique_ptr<DeviceSetup> maps;
  RawRegisterSource raw;
  dissect::DevicePointSource source{&raw};

  ReportPoints() = default;
  ReportPoints(const ReportPoints&) = delete;
  ReportPoints& operator=(const ReportPoints&) = delete;
};

// Feeds the capture (as `options` replay it) to a sink: how identification gets to see the
// traffic before the report pass.
using TrafficFeed = std::function<void(const ReplayOptions& options, RecordSink& sink)>;

// Builds the point source. Fills in `options` from a bus file like DeviceOptions::build.
// The annotator in `maps` knows the configured slaves too, for the frame writers. A live
// run has no traffic to show in advance and passes no feed: only configured slaves are
// named there.
// When `identify` is given, it runs once with a MapIdentifier before this returns (reader
// warnings off; an InputError in it is left for the report pass to raise). Throws
// InputError for bad device options or maps.
[[nodiscard]] std::unique_ptr<ReportPoints> build_report_points(const DeviceOptions& devices,
                                                                ReplayOptions& options,
                                                                const TrafficFeed& identify = {});

}  // namespace rtu::app
