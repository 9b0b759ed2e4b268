#include "app/identify_models.hpp"

#include "core/input_error.hpp"
#include "dissect/map_identifier.hpp"
#include "pairing/transaction_tracker.hpp"

namespace rtu::app {

namespace {

// Measures the sample on its way to the identifier, so the look can end after it: each frame
// counts one, and so does each byte of noise. Noise is the dearest traffic to frame (every
// byte may start a frame whose CRC is searched), and the costliest to hold, so a capture of a
// sick bus, or one read at the wrong baud rate, has a sample no longer than others'.
class SampleMeter final : public RecordSink {
 public:
  explicit SampleMeter(RecordSink& next) : next_(next) {}
  void on_record(Record& record) override {
    if (record.kind == RecordKind::kFrame) {
      ++frames;
    } else {
      noise_bytes += record.size;
    }
    next_.on_record(record);
  }
  [[nodiscard]] std::uint64_t measured() const { return frames + noise_bytes; }
  std::uint64_t frames = 0;
  std::uint64_t noise_bytes = 0;

 private:
  RecordSink& next_;
};

}  // namespace

struct IdentifyingLook::Sample {
  Sample(const dissect::MapLibrary& library, const CaptureInfo& info)
      : identifier(library, kIdentifyRequestsPerSlave),
        meter(identifier),
        tracker(TrackerConfig{info.response_timeout}, meter) {}
  dissect::MapIdentifier identifier;
  SampleMeter meter;
  TransactionTracker tracker;
};

IdentifyingLook::IdentifyingLook(DeviceSetup& devices, std::uint64_t sample_frames)
    : devices_(devices), sample_frames_(sample_frames) {
  looked_at_.frames_wanted = sample_frames;
  looked_at_.held_bound_bytes = FirstLook::kMaxHeldBytes;
}

IdentifyingLook::~IdentifyingLook() = default;

PairingInput& IdentifyingLook::start_look(const CaptureInfo& info) {
  sample_ = std::make_unique<Sample>(devices_.library, info);
  return sample_->tracker;
}

bool IdentifyingLook::seen_enough() const {
  return sample_ != nullptr && sample_->meter.measured() >= sample_frames_;
}

void IdentifyingLook::conclude(SampleEnd why) {
  if (sample_ == nullptr) return;
  devices_.table.assign_identified(sample_->identifier.ranking());
  looked_at_.frames = sample_->meter.frames;
  looked_at_.noise_bytes = sample_->meter.noise_bytes;
  looked_at_.end = why;
  sample_.reset();
}

IdentificationSample identify_from_whole_capture(DeviceSetup& devices, const ReplayOptions& options,
                                                 const TrafficFeed& feed) {
  dissect::MapIdentifier identifier(devices.library);
  SampleMeter meter(identifier);
  ReplayOptions quiet = options;
  quiet.show_warnings = false;
  quiet.on_chunk = nullptr;
  try {
    feed(quiet, meter);
  } catch (const InputError&) {
    // Damaged input: identify from what precedes the damage; the report pass says where.
  }
  devices.table.assign_identified(identifier.ranking());
  return IdentificationSample{0, meter.frames, meter.noise_bytes, SampleEnd::kCaptureEnd};
}

}  // namespace rtu::app
