#include "app/report_points.hpp"

#include "core/input_error.hpp"
#include "dissect/map_identifier.hpp"

namespace rtu::app {

std::unique_ptr<ReportPoints> build_report_points(const DeviceOptions& devices,
                                                  ReplayOptions& options,
                                                  const TrafficFeed& identify) {
  auto points = std::make_unique<ReportPoints>();
  points->maps = devices.build(options);
  if (!points->maps) points->maps = DeviceOptions::load_maps(devices.dissector_dirs);
  const dissect::DeviceAnnotator& configured = points->maps->annotator;
  for (unsigned a = 0; a < 256; ++a) {
    const auto slave = static_cast<std::uint8_t>(a);
    if (const dissect::DeviceMap* map = configured.model_of(slave)) {
      points->source.assign(slave, *map, dissect::ModelOrigin::kConfigured);
    }
  }
  if (!identify || points->maps->library.maps().empty()) return points;

  dissect::MapIdentifier identifier(points->maps->library);
  ReplayOptions quiet = options;
  quiet.show_warnings = false;
  quiet.on_chunk = nullptr;
  try {
    identify(quiet, identifier);
  } catch (const InputError&) {
    // Damaged input: identify from what precedes the damage; the report pass says where.
  }
  points->source.assign_identified(identifier.ranking());  // configured slaves keep theirs
  return points;
}

}  // namespace rtu::app
