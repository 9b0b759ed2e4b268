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
    measured += record.kind == RecordKind::kFrame ? 1 : record.size;
    next_.on_record(record);
  }
  std::uint64_t measured = 0;

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
    : devices_(devices), sample_frames_(sample_frames) {}

IdentifyingLook::~IdentifyingLook() = default;

PairingInput& IdentifyingLook::start_look(const CaptureInfo& info) {
  sample_ = std::make_unique<Sample>(devices_.library, info);
  return sample_->tracker;
}

bool IdentifyingLook::seen_enough() const {
  return sample_ != nullptr && sample_->meter.measured >= sample_frames_;
}

void IdentifyingLook::conclude() {
  if (sample_ == nullptr) return;
  devices_.table.assign_identified(sample_->identifier.ranking());
  sample_.reset();
}

void identify_from_whole_capture(DeviceSetup& devices, const ReplayOptions& options,
                                 const TrafficFeed& feed) {
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
