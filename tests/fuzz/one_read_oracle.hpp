#pragma once
// What the fuzz targets of capture readers assert about reading a capture once: a file that
// declares its settings and is decoded in one read (declared_survey, decode_and_survey, as
// `report` and `export` read it) gives the same records and the same capture description
// (warnings included) as when it is surveyed first, or answers "decode it again", never
// something else.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "framing/record.hpp"
#include "pipeline/replay.hpp"

namespace rtu::fuzz {

// Every record as one line of what it shows, to compare two decodings; fails `target` on a
// record of no bytes, of more than 256, or ending before it starts.
class RecordTranscript final : public RecordSink {
 public:
  explicit RecordTranscript(std::string_view target) : target_(target) {}
  void on_record(Record& record) override;
  std::size_t bytes = 0;
  std::vector<std::string> seen;

 private:
  std::string_view target_;
};

// `surveyed_first`: the records replay_capture(open, options) gave; `surveyed_info`: what it
// returned, or nullopt when it found the file damaged.
void check_one_read(std::string_view target, const CaptureOpener& open,
                    const ReplayOptions& options, const RecordTranscript& surveyed_first,
                    const std::optional<CaptureInfo>& surveyed_info);

}  // namespace rtu::fuzz
