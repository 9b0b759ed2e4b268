// Fuzz target for the text hex reader (capture/text_hex_reader.hpp): the input is the file.
// Oracles:
// - the reader (capture_checks.hpp): chunks of at least one byte, line numbers as origins,
//   times never going backwards (the reader clamps them), and an end or an InputError naming
//   a line; also, what it declares from "# baud=..." comments is a usable line;
// - the replay (replay_capture, two passes): every byte read leaves in exactly one record,
//   and damage ends it with an InputError naming a line;
// - one read for a file that declares its line settings (one_read_oracle.hpp), as `report`
//   and `export` read a per-byte text capture with a "# baud=..." line;
// - the reading of data lines in place in the line buffer: the same text with a blank before
//   every line (which that reading refuses, so every line is read line by line) gives the
//   same items, and fails where the original fails;
// - read_many(), which parses one-byte lines straight into runs: the same items as read()
//   at a room of a few reads and of a whole run.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "capture/text_hex_reader.hpp"
#include "capture_checks.hpp"
#include "core/input_error.hpp"
#include "fuzz_input_file.hpp"
#include "fuzz_oracle.hpp"
#include "one_read_oracle.hpp"
#include "pipeline/replay.hpp"

namespace {

constexpr std::string_view kTarget = "fuzz_text_hex";

// `text` with a blank before every line (after a byte-order mark, which only starts line 1).
std::string blank_before_every_line(std::string_view text) {
  constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
  std::string out;
  out.reserve(text.size() + text.size() / 8 + 1);
  if (text.substr(0, kUtf8Bom.size()) == kUtf8Bom) {
    out += kUtf8Bom;
    text.remove_prefix(kUtf8Bom.size());
  }
  bool line_start = true;
  for (const char c : text) {
    if (line_start) out += ' ';
    out += c;
    line_start = c == '\n';
  }
  return out;
}

bool same_items(const rtu::fuzz::CaptureRead& a, const rtu::fuzz::CaptureRead& b) {
  if (a.failed != b.failed || a.items.size() != b.items.size()) return false;
  for (std::size_t i = 0; i < a.items.size(); ++i) {
    const auto& x = a.items[i];
    const auto& y = b.items[i];
    if (x.kind != y.kind || x.bytes != y.bytes || x.t != y.t || x.origin != y.origin) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto& file = rtu::fuzz::fuzz_input_file();
  file.write(data, size);
  const std::string& path = file.path();
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  rtu::fuzz::CaptureRules rules;
  rules.target = kTarget;
  rules.text = text;
  rules.times_in_order = true;
  rules.origins_are_lines = true;
  const rtu::CaptureOpener open = [&path](rtu::WarningSink warnings) {
    return std::make_unique<rtu::TextHexReader>(path, std::move(warnings));
  };
  const rtu::fuzz::CaptureRead read = rtu::fuzz::read_and_check(open, path, rules);

  rtu::ReplayOptions options;
  options.show_warnings = false;
  rtu::fuzz::RecordTranscript sink(kTarget);
  std::optional<rtu::CaptureInfo> surveyed_info;
  try {
    surveyed_info = rtu::replay_capture(open, options, sink);
  } catch (const rtu::InputError& e) {
    rtu::fuzz::require_line(kTarget, e.what(), path, rtu::fuzz::count_lines(text));
  } catch (const std::exception& e) {
    rtu::fuzz::fail(kTarget, "replay threw something other than InputError", e.what());
  }
  if (!surveyed_info != read.failed) {
    rtu::fuzz::fail(kTarget, "the replay and the reader disagree on the damage", "");
  }
  std::size_t bytes_read = 0;
  for (const auto& item : read.items) bytes_read += item.bytes.size();
  if (sink.bytes != bytes_read) {
    rtu::fuzz::fail(kTarget, "bytes lost or duplicated between the reader and the records",
                    std::to_string(sink.bytes) + " of " + std::to_string(bytes_read));
  }
  rtu::fuzz::check_one_read(kTarget, open, options, sink, surveyed_info);

  for (const std::size_t room : {std::size_t{1} + size % 5, std::size_t{4096}}) {
    rtu::fuzz::CaptureRules many = rules;
    many.read_many_room = room;
    if (!same_items(read, rtu::fuzz::read_and_check(open, path, many))) {
      rtu::fuzz::fail(kTarget, "read_many() and read() disagree", std::to_string(room));
    }
  }

  const std::string line_by_line = blank_before_every_line(text);
  file.write(reinterpret_cast<const std::uint8_t*>(line_by_line.data()), line_by_line.size());
  rules.text = line_by_line;
  if (!same_items(read, rtu::fuzz::read_and_check(open, path, rules))) {
    rtu::fuzz::fail(kTarget, "reading lines in place and line by line disagree", "");
  }
  return 0;
}
