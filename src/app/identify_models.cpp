#include "app/identify_models.hpp"

#include "core/input_error.hpp"
#include "dissect/map_identifier.hpp"

namespace rtu::app {

void identify_models(DeviceSetup& devices, const ReplayOptions& options, const TrafficFeed& feed) {
  if (devices.library.maps().empty()) return;
  dissect::MapIdentifier identifier(devices.library);
  ReplayOptions quiet = options;
  quiet.show_warnings = false;
  quiet.on_chunk = nullptr;
  try {
    feed(quiet, identifier);
  } catch (const InputError&) {
    // Damaged input: identify from what precedes the damage; the report pass says where.
  }
  devices.table.assign_identified(identifier.ranking());
}

}  // namespace rtu::app
