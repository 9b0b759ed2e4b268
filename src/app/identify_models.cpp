#include "app/identify_models.hpp"

#include "core/input_error.hpp"
#include "dissect/map_identifier.hpp"

namespace rtu::app {

namespace {

// Measures the sample on its way to the identifier, so the pass can end after it: each frame
// counts one, and so does each byte of noise. Noise is the dearest traffic to frame (every
// byte may start a frame whose CRC is searched), so a capture of a sick bus, or one read at
// the wrong baud rate, would otherwise be framed twice over before its first frames.
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

void identify_models(DeviceSetup& devices, const ReplayOptions& options,
                     std::uint64_t sample_frames, const TrafficFeed& feed) {
  if (devices.library.maps().empty()) return;
  dissect::MapIdentifier identifier(devices.library,
                                    sample_frames > 0 ? kIdentifyRequestsPerSlave : 0);
  SampleMeter meter(identifier);
  ReplayOptions quiet = options;
  quiet.show_warnings = false;
  quiet.on_chunk = nullptr;
  if (sample_frames > 0) {
    quiet.enough = [&meter, sample_frames] { return meter.measured >= sample_frames; };
  }
  try {
    feed(quiet, meter);
  } catch (const InputError&) {
    // Damaged input: identify from what precedes the damage; the report pass says where.
  }
  devices.table.assign_identified(identifier.ranking());
}

}  // namespace rtu::app
