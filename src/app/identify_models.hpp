#pragma once
// Slaves no option names get the model the MapIdentifier is confident about, from a first
// look at the capture's first frames (the first pass of `report`). The models go into the device
// table that the device stage decodes with in the second pass; configured slaves keep theirs.
#include <cstdint>
#include <functional>

#include "app/device_options.hpp"
#include "framing/record.hpp"
#include "pipeline/replay.hpp"

namespace rtu::app {

// Feeds the capture (as `options` replay it) to a sink.
using TrafficFeed = std::function<void(const ReplayOptions& options, RecordSink& sink)>;

// How many frames identification looks at by default: minutes to hours of a busy bus, in
// which every polled slave answers many times, and a small part of a long capture's report.
inline constexpr std::uint64_t kIdentifySampleFrames = 200'000;
// Requests of one slave after which its evidence is complete: a confident model needs 10,
// and 2,000 show every register block a master polls many times over.
inline constexpr std::uint64_t kIdentifyRequestsPerSlave = 2'000;

// Runs `feed` once with a MapIdentifier (reader warnings off) over the first `sample_frames`
// frames, a byte of noise counting as a frame (0 = all, and every request weighed), and
// assigns what it is sure of. An InputError in this pass is left for the next pass to raise,
// with everything before the damage identified.
void identify_models(DeviceSetup& devices, const ReplayOptions& options,
                     std::uint64_t sample_frames, const TrafficFeed& feed);

}  // namespace rtu::app
