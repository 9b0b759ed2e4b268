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
// - one read for a file that declares its settings (one_read_oracle.hpp), as `report` and
//   `export` read rtuscope's own recordings.
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
#include "one_read_oracle.hpp"
#include "pipeline/replay.hpp"

namespace {

constexpr std::string_view kTarget = "fuzz_pcap";

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
  rtu::fuzz::RecordTranscript sink(kTarget);
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
  rtu::fuzz::check_one_read(kTarget, open, options, sink, surveyed_info);
  return 0;
}
