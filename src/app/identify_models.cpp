#include "app/identify_models.hpp"

#include "core/input_error.hpp"
#include "dissect/map_identifier.hpp"

namespace rtu::app {

namespace {

// Counts the frames on their way to the identifier, so the pass can end after a sample.
class FrameCounter final : public RecordSink {
 public:
  explicit FrameCounter(RecordSink& next) : next_(next) {}
  void on_record(Record& record) override {
    if (record.kind == RecordKind::kFrame) ++frames;
    next_.on_record(record);
  }
  std::uint64_t frames = 0;

 private:
  RecordSink& next_;
};

}  // namespace

void identify_models(DeviceSetup& devices, const ReplayOptions& options,
                     std::uint64_t sample_frames, const TrafficFeed& feed) {
  if (devices.library.maps().empty()) return;
  dissect::MapIdentifier identifier(devices.library,
                                    sample_frames > 0 ? kIdentifyRequestsPerSlave : 0);
  FrameCounter counter(identifier);
  ReplayOptions quiet = options;
  quiet.show_warnings = false;
  quiet.on_chunk = nullptr;
  if (sample_frames > 0) {
    quiet.enough = [&counter, sample_frames] { return counter.frames >= sample_frames; };
  }
  try {
    feed(quiet, counter);
  } catch (const InputError&) {
    // Damaged input: identify from what precedes the damage; the report pass says where.
  }
  devices.table.assign_identified(identifier.ranking());
}

}  // namespace rtu::app
