#pragma once
// Slaves no option names get the model the MapIdentifier is confident about, from a first
// look at the whole capture (the first pass of `report`). The models go into the device table
// that the device stage decodes with in the second pass; configured slaves keep theirs.
#include <functional>

#include "app/device_options.hpp"
#include "framing/record.hpp"
#include "pipeline/replay.hpp"

namespace rtu::app {

// Feeds the capture (as `options` replay it) to a sink.
using TrafficFeed = std::function<void(const ReplayOptions& options, RecordSink& sink)>;

// Runs `feed` once with a MapIdentifier (reader warnings off) and assigns what it is sure of.
// An InputError in this pass is left for the next pass to raise, with everything before the
// damage identified.
void identify_models(DeviceSetup& devices, const ReplayOptions& options, const TrafficFeed& feed);

}  // namespace rtu::app
