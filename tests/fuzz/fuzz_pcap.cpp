// Fuzz target for pcap and pcapng captures (capture/pcap_capture_reader.hpp), both link
// types rtuscope reads: 250 (raw serial reads and line events) and 252 (Wireshark upper-PDU
// records, one Modbus RTU frame or noise each). The input is the file.
//
// Oracles:
// - the reader (capture_checks.hpp): chunks of at least one byte, origins inside the file,
//   an end or an InputError naming an offset, nothing delivered after it;
// - the import path: the file replayed as `rtuscope decode` replays it (replay_capture:
//   raw reads re-framed when there are any, else the frame records decoded as they are)
//   gives records of 1..256 bytes ending no earlier than they start, and every byte the
//   reader delivered leaves in exactly one record; a damaged file ends the replay with an
//   InputError naming where;
// - one read for a file that declares its settings (declared_survey, decode_and_survey, as
//   `report` and `export` read rtuscope's own recordings): the same records and the same
//   capture description (warnings included) as surveyed first, or an answer of "decode it
//   again" (a declaration later in the file), never something else.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "capture/pcap_capture_reader.hpp"
#include "capture_checks.hpp"
#include "core/input_error.hpp"
#include "framing/record.hpp"
#include "fuzz_input_file.hpp"
#include "fuzz_oracle.hpp"
#include "pipeline/replay.hpp"

namespace {

constexpr std::string_view kTarget = "fuzz_pcap";

class CountingSink final : public rtu::RecordSink {
 public:
  void on_record(rtu::Record& record) override {
    if (record.size == 0 || record.size > rtu::kMaxAdu) {
      rtu::fuzz::fail(kTarget, "record size outside 1..256", std::to_string(record.size));
    }
    if (record.t_end < record.t_start) rtu::fuzz::fail(kTarget, "record ends before it starts", "");
    bytes += record.size;
    const auto b = record.bytes();
    seen.push_back(std::to_string(static_cast<int>(record.kind)) + " " +
                   std::string(b.begin(), b.end()) + " " + std::to_string(record.t_start) + " " +
                   std::to_string(record.t_end) + " " + std::to_string(record.gap_before) + " " +
                   std::to_string(record.issues.bits()) + " " +
                   std::to_string(static_cast<int>(record.role)) + " " +
                   std::to_string(record.txn) + " " + std::to_string(record.latency));
  }
  std::size_t bytes = 0;
  std::vector<std::string> seen;  // what each record shows, to compare two decodings
};

// What a capture's description tells the user, to compare two surveys.
std::string described(const rtu::CaptureInfo& info) {
  std::string text = info.source + " " + info.line.describe() + " " +
                     std::to_string(info.timing_resolution) + " " +
                     std::to_string(info.response_timeout) + " " +
                     std::to_string(static_cast<int>(info.per_byte_timing));
  for (const auto& warning : info.warnings) text += "\n" + warning;
  return text;
}

// The one-read path against the two-pass one, on a file whose start declares its settings.
void check_declared_survey(const rtu::CaptureOpener& open, const rtu::ReplayOptions& options,
                           const CountingSink& surveyed_first,
                           const std::optional<rtu::CaptureInfo>& surveyed_info) {
  std::optional<rtu::CaptureSurvey> declared;
  try {
    declared = rtu::declared_survey(open, options);
  } catch (const rtu::InputError& e) {
    // Only a file the two passes could not read either (not a capture at all).
    if (surveyed_info)
      rtu::fuzz::fail(kTarget, "declared_survey failed on a readable file", e.what());
    return;
  } catch (const std::exception& e) {
    rtu::fuzz::fail(kTarget, "declared_survey threw something other than InputError", e.what());
  }
  if (!declared) return;
  CountingSink alongside;
  std::optional<rtu::CaptureInfo> info;
  try {
    info = rtu::decode_and_survey(open, *declared, options, alongside);
  } catch (const rtu::InputError&) {
    if (surveyed_info) rtu::fuzz::fail(kTarget, "only the one-read decoding found damage", "");
    return;
  }
  if (!info) return;  // decode it again: the two-pass decoding is the answer
  if (!surveyed_info) rtu::fuzz::fail(kTarget, "only the two-pass decoding found damage", "");
  if (alongside.seen != surveyed_first.seen) {
    rtu::fuzz::fail(kTarget, "records differ between one read and two passes",
                    std::to_string(alongside.seen.size()) + " and " +
                        std::to_string(surveyed_first.seen.size()) + " records");
  }
  if (described(*info) != described(*surveyed_info)) {
    rtu::fuzz::fail(kTarget, "the capture's description differs between one read and two passes",
                    described(*info) + " | " + described(*surveyed_info));
  }
}

// Bytes the replay must account for: the raw reads when there are any, else the frame and
// noise records.
std::size_t bytes_to_decode(const rtu::fuzz::CaptureRead& read) {
  std::size_t chunk_bytes = 0;
  std::size_t record_bytes = 0;
  bool any_chunk = false;
  for (const auto& item : read.items) {
    if (item.kind == rtu::fuzz::CaptureItem::Kind::kChunk) {
      any_chunk = true;
      chunk_bytes += item.bytes.size();
    } else {
      record_bytes += item.bytes.size();
    }
  }
  return any_chunk ? chunk_bytes : record_bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto& file = rtu::fuzz::fuzz_input_file();
  file.write(data, size);
  const std::string& path = file.path();
  rtu::fuzz::CaptureRules rules;
  rules.target = kTarget;
  rules.text = std::string_view(reinterpret_cast<const char*>(data), size);
  rules.origins_are_lines = false;
  const rtu::CaptureOpener open = [&path](const rtu::WarningSink& warnings) {
    return std::make_unique<rtu::PcapCaptureReader>(path, warnings);
  };
  const rtu::fuzz::CaptureRead read = rtu::fuzz::read_and_check(open, path, rules);

  rtu::ReplayOptions options;
  options.show_warnings = false;
  CountingSink sink;
  bool replay_failed = false;
  std::optional<rtu::CaptureInfo> surveyed_info;
  try {
    surveyed_info = rtu::replay_capture(open, options, sink);
  } catch (const rtu::InputError& e) {
    rtu::fuzz::require_offset(kTarget, e.what(), path, size);
    replay_failed = true;
  } catch (const std::exception& e) {
    rtu::fuzz::fail(kTarget, "replay threw something other than InputError", e.what());
  }
  if (replay_failed != read.failed) {
    rtu::fuzz::fail(kTarget, "the replay and the reader disagree on the damage", "");
  }
  if (sink.bytes != bytes_to_decode(read)) {
    rtu::fuzz::fail(kTarget, "bytes lost or duplicated between the reader and the records",
                    std::to_string(sink.bytes) + " of " + std::to_string(bytes_to_decode(read)));
  }
  check_declared_survey(open, options, sink, surveyed_info);
  return 0;
}
