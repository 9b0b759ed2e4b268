#include "report/text_writer.hpp"

#include <iterator>
#include <optional>

#include "core/function_codes.hpp"
#include "core/time_format.hpp"
#include "dissect/device_stage.hpp"
#include "dissect/point_format.hpp"
#include "modbus/pdu.hpp"
#include "report/frame_text.hpp"
#include "report/timing_note.hpp"

namespace rtu {
namespace {

constexpr std::size_t kHexPreview = 24;  // bytes shown for noise and undecodable frames

void append_hex_preview(fmt::memory_buffer& out, std::span<const std::uint8_t> bytes) {
  const std::size_t shown = bytes.size() < kHexPreview ? bytes.size() : kHexPreview;
  for (std::size_t i = 0; i < shown; ++i) {
    fmt::format_to(std::back_inserter(out), "{}{:02x}", i == 0 ? "" : " ", bytes[i]);
  }
  if (shown < bytes.size()) fmt::format_to(std::back_inserter(out), " …");
}

void pad_to(fmt::memory_buffer& out, std::size_t line_start, std::size_t column) {
  while (out.size() - line_start < column) out.push_back(' ');
}

}  // namespace

void append_frame_summary(fmt::memory_buffer& out, const Record& frame) {
  if (frame.role == Role::kUnknown && !frame.is_exception()) {
    append_hex_preview(out, frame.bytes());  // nothing to say what its fields mean
    return;
  }
  // The function already has its own column: leave out the summary's leading name.
  fmt::memory_buffer summary;
  std::optional<DecodedPdu> scratch;
  append_pdu_summary(summary, decoding_of(frame, frame.role, scratch));
  std::string_view text(summary.data(), summary.size());
  const std::string_view name = function_short_name(frame.function());
  if (text.size() > name.size() && text.substr(0, name.size()) == name &&
      text[name.size()] == ' ') {
    text.remove_prefix(name.size() + 1);
  }
  out.append(text);
}

TextWriter::TextWriter(OutputStream& out) : out_(out) {}

void TextWriter::on_capture(const CaptureInfo& info) {
  buffer_.clear();
  auto it = std::back_inserter(buffer_);
  fmt::format_to(it, "# {}  line {}  char {:.3f} ms  t1.5 {:.3f} ms  t3.5 {:.3f} ms\n", info.source,
                 info.line.describe(), to_millis(info.line.char_time()),
                 to_millis(info.line.t1_5()), to_millis(info.line.t3_5()));
  fmt::format_to(it, "# timing: {}\n", timing_note(info));
  for (const std::string& w : info.warnings) fmt::format_to(it, "# warning: {}\n", w);
  fmt::format_to(it, "# {:>18} {:>11}  {:<4} {:>5}  {:<16} {}\n", "time [s]", "gap", "role",
                 "slave", "function", "summary   latency   [issues]");
  out_.write(buffer_);
}

void TextWriter::on_record(Record& record) {
  const bool is_frame = record.kind == RecordKind::kFrame;
  // The device stage (when one runs) read the frame with the slave's map.
  const dissect::DeviceMap* map = record.device != nullptr ? record.device->map : nullptr;
  buffer_.clear();
  auto it = std::back_inserter(buffer_);
  if (record.t_start >= kWallClockFrom && utc_day(record.t_start) != shown_day_) {
    // Wall-clock times (live, pcap) read best as the time of day; a line names the date
    // before the first record and whenever it changes.
    shown_day_ = utc_day(record.t_start);
    buffer_.append(std::string_view("# "));
    append_utc_date(buffer_, record.t_start);
    buffer_.append(std::string_view(" (UTC): times are the time of day\n"));
  }
  const std::size_t start = buffer_.size();
  buffer_.push_back(' ');
  buffer_.push_back(' ');
  pad_to(buffer_, start, 2);
  {
    fmt::memory_buffer t;
    if (record.t_start >= kWallClockFrom) {
      append_utc_time_of_day(t, record.t_start, 6);
    } else {
      append_seconds(t, record.t_start, 6);
    }
    fmt::format_to(it, "{:>18}", std::string_view(t.data(), t.size()));
  }
  if (record.gap_before == kUnknownTime) {
    fmt::format_to(it, " {:>11}", "?");
  } else {
    fmt::format_to(it, " {:>+9.3f}ms", to_millis(record.gap_before));
  }
  if (!is_frame) {
    fmt::format_to(it, "  {:<4} {:>5}  {:<16} {} {}: ", "noise", "", "", record.size,
                   record.size == 1 ? "byte" : "bytes");
    append_hex_preview(buffer_, record.bytes());
  } else {
    fmt::format_to(it, "  {:<4} {:>5}  {:<16} ", role_short_name(record.role), record.slave(),
                   function_short_name(record.function()));
    const std::string_view vendor_exception =
        map != nullptr && record.is_exception() && record.size >= 3
            ? map->exception_name(record.storage[2])
            : std::string_view{};
    if (!vendor_exception.empty()) {
      fmt::format_to(it, "exception {:02X} {}", record.storage[2], vendor_exception);
    } else {
      append_frame_summary(buffer_, record);
    }
    if (map != nullptr) dissect::append_points_text(buffer_, record.device->decoded);
    if (record.role == Role::kResponse && record.latency != kUnknownTime) {
      fmt::format_to(it, "  {:.3f} ms", to_millis(record.latency));
    }
    if (record.txn >= 0) fmt::format_to(it, "  #{}", record.txn);
  }
  if (!record.issues.empty()) {
    buffer_.append(std::string_view("  ["));
    bool first = true;
    record.issues.for_each([&](IssueId id) {
      if (!first) buffer_.push_back(' ');
      first = false;
      buffer_.append(issue_info(id).key);
    });
    buffer_.push_back(']');
  }
  buffer_.push_back('\n');
  out_.write(buffer_);
}

void TextWriter::on_finish() {
  out_.flush();
}

}  // namespace rtu
