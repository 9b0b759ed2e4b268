#pragma once
// Slaves no option names get the model the MapIdentifier is confident about, from a first
// look at the capture's first frames (`report`). The models go into the device table that the
// device stage decodes with, before it decodes the first frame; configured slaves keep theirs.
#include <cstdint>
#include <functional>
#include <memory>

#include "app/device_options.hpp"
#include "framing/record.hpp"
#include "pipeline/first_look.hpp"
#include "pipeline/replay.hpp"
#include "report/identification_sample.hpp"

namespace rtu::app {

// Feeds the capture (as `options` replay it) to a sink.
using TrafficFeed = std::function<void(const ReplayOptions& options, RecordSink& sink)>;

// How many frames identification looks at by default: minutes to hours of a busy bus, in
// which every polled slave answers many times, and a small part of a long capture's report.
inline constexpr std::uint64_t kIdentifySampleFrames = 200'000;
// Requests of one slave after which its evidence is complete: a confident model needs 10,
// and 2,000 show every register block a master polls many times over.
inline constexpr std::uint64_t kIdentifyRequestsPerSlave = 2'000;

// Identification in the decoding pass itself (ReplayOptions::first_look): the pass's first
// `sample_frames` frames (> 0), a byte of noise counting as a frame, go to a MapIdentifier
// first, and before the sink gets any of them the slaves get what it is sure of. The sample
// also ends where the records held for the sink reach FirstLook::kMaxHeldBytes: 200,000
// frames of 256 bytes would hold about 60 MB, and a third of them identify as well.
class IdentifyingLook final : public FirstLook {
 public:
  IdentifyingLook(DeviceSetup& devices, std::uint64_t sample_frames);
  ~IdentifyingLook() override;
  IdentifyingLook(const IdentifyingLook&) = delete;
  IdentifyingLook& operator=(const IdentifyingLook&) = delete;
  IdentifyingLook(IdentifyingLook&&) = delete;
  IdentifyingLook& operator=(IdentifyingLook&&) = delete;

  PairingInput& start_look(const CaptureInfo& info) override;
  [[nodiscard]] bool seen_enough() const override;
  void conclude(SampleEnd why) override;

  // What the look looked at, once it concluded.
  [[nodiscard]] const IdentificationSample& looked_at() const { return looked_at_; }

 private:
  struct Sample;
  DeviceSetup& devices_;
  std::uint64_t sample_frames_;
  std::unique_ptr<Sample> sample_;
  IdentificationSample looked_at_;
};

// Runs `feed` once to the end with a MapIdentifier (reader warnings off) that weighs every
// request, and assigns what it is sure of: identification from the whole capture, which is
// too long to hold for an IdentifyingLook. An InputError in this pass is left for the next
// pass to raise, with everything before the damage identified. Returns what it looked at.
IdentificationSample identify_from_whole_capture(DeviceSetup& devices, const ReplayOptions& options,
                                                 const TrafficFeed& feed);

}  // namespace rtu::app
