#include "one_read_oracle.hpp"

#include <exception>

#include "core/input_error.hpp"
#include "fuzz_oracle.hpp"

namespace rtu::fuzz {

void RecordTranscript::on_record(Record& record) {
  if (record.size == 0 || record.size > kMaxAdu) {
    fail(target_, "record size outside 1..256", std::to_string(record.size));
  }
  if (record.t_end < record.t_start) fail(target_, "record ends before it starts", "");
  bytes += record.size;
  const auto b = record.bytes();
  seen.push_back(std::to_string(static_cast<int>(record.kind)) + " " +
                 std::string(b.begin(), b.end()) + " " + std::to_string(record.t_start) + " " +
                 std::to_string(record.t_end) + " " + std::to_string(record.gap_before) + " " +
                 std::to_string(record.issues.bits()) + " " +
                 std::to_string(static_cast<int>(record.role)) + " " + std::to_string(record.txn) +
                 " " + std::to_string(record.latency));
}

namespace {

// What a capture's description tells the user, to compare two surveys.
std::string described(const CaptureInfo& info) {
  std::string text =
      info.source + " " + info.line.describe() + " " + std::to_string(info.timing_resolution) +
      " " + std::to_string(info.learned_resolution) + " " + std::to_string(info.response_timeout) +
      " " + std::to_string(static_cast<int>(info.per_byte_timing));
  for (const auto& warning : info.warnings) text += "\n" + warning;
  return text;
}

}  // namespace

void check_one_read(std::string_view target, const CaptureOpener& open,
                    const ReplayOptions& options, const RecordTranscript& surveyed_first,
                    const std::optional<CaptureInfo>& surveyed_info) {
  std::optional<CaptureSurvey> declared;
  try {
    declared = declared_survey(open, options);
  } catch (const InputError& e) {
    // Only a file the two passes could not read either (not a capture at all).
    if (surveyed_info) fail(target, "declared_survey failed on a readable file", e.what());
    return;
  } catch (const std::exception& e) {
    fail(target, "declared_survey threw something other than InputError", e.what());
  }
  if (!declared) return;
  RecordTranscript alongside(target);
  std::optional<CaptureInfo> info;
  try {
    info = decode_and_survey(open, *declared, options, alongside);
  } catch (const InputError&) {
    if (surveyed_info) fail(target, "only the one-read decoding found damage", "");
    return;
  }
  if (!info) return;  // decode it again: the two-pass decoding is the answer
  if (!surveyed_info) fail(target, "only the two-pass decoding found damage", "");
  if (alongside.seen != surveyed_first.seen) {
    fail(target, "records differ between one read and two passes",
         std::to_string(alongside.seen.size()) + " and " +
             std::to_string(surveyed_first.seen.size()) + " records");
  }
  if (described(*info) != described(*surveyed_info)) {
    fail(target, "the capture's description differs between one read and two passes",
         described(*info) + " | " + described(*surveyed_info));
  }
}

}  // namespace rtu::fuzz
