#include "capture/rtac_serial.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>

#include "capture/byte_order.hpp"

namespace rtu {

std::string_view rtac_event_name(std::uint8_t event) {
  static constexpr std::array<std::string_view, 11> kNames = {
      "STATUS_CHANGE", "DATA_TX_START",      "DATA_RX_START",        "DATA_TX_END",
      "DATA_RX_END",   "CAPTURE_DATA_LOST",  "CAPTURE_COMPLETE",     "FRAMING_ERROR",
      "PARITY_ERROR",  "SERIAL_BREAK_EVENT", "SERIAL_OVERFLOW_EVENT"};
  return event < kNames.size() ? kNames[event] : std::string_view("UNKNOWN");
}

void build_rtac_record(Nanos t, RtacEvent event, std::uint8_t control_lines,
                       std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& out) {
  const Nanos clamped = t < 0 ? 0 : t;
  out.clear();
  append<std::uint32_t>(out, static_cast<std::uint32_t>(clamped / kNanosPerSecond),
                        ByteOrder::kBig);
  append<std::uint32_t>(out, static_cast<std::uint32_t>((clamped % kNanosPerSecond) / 1000),
                        ByteOrder::kBig);
  out.push_back(static_cast<std::uint8_t>(event));
  out.push_back(control_lines);
  append<std::uint16_t>(out, 0, ByteOrder::kBig);
  out.insert(out.end(), payload.begin(), payload.end());
}

std::optional<RtacRecord> parse_rtac_record(std::span<const std::uint8_t> record,
                                            std::string& error) {
  if (record.size() < kRtacHeaderSize) {
    error = fmt::format("RTAC serial record of {} bytes is shorter than its {}-byte header",
                        record.size(), kRtacHeaderSize);
    return std::nullopt;
  }
  RtacRecord r;
  r.seconds = load_u32(record, 0, ByteOrder::kBig);
  r.micros = load_u32(record, 4, ByteOrder::kBig);
  r.event = record[kRtacEventOffset];
  r.control_lines = record[9];
  r.footer = load_u16(record, 10, ByteOrder::kBig);
  r.payload = record.subspan(kRtacHeaderSize);
  return r;
}

ReadTimeMarks time_marks_of(const Chunk& chunk, Nanos record_time) {
  ReadTimeMarks marks{chunk.read_late, chunk.time_clamped, kUnknownTime};
  if (chunk.read_late && chunk.quiet_until != kUnknownTime && chunk.quiet_until <= record_time) {
    marks.quiet_before = record_time - chunk.quiet_until;
  }
  return marks;
}

std::string time_marks_comment(ReadTimeMarks marks) {
  std::string comment;
  const auto line = [&](std::string_view text) {
    if (!comment.empty()) comment += '\n';
    comment += text;
  };
  if (marks.read_late) {
    line(kReadLateComment);
    if (marks.quiet_before != kUnknownTime) {
      line(fmt::format("{}{}{}", kPortEmptyComment, marks.quiet_before, kPortEmptyCommentEnd));
    }
  }
  if (marks.time_clamped) line(kTimeClampedComment);
  return comment;
}

ReadTimeMarks time_marks_of(std::string_view comment) {
  ReadTimeMarks marks;
  if (comment.empty()) return marks;
  marks.read_late = comment.find(kReadLateComment) != std::string_view::npos;
  marks.time_clamped = comment.find(kTimeClampedComment) != std::string_view::npos;
  // The number, only as written (anything else leaves it unknown).
  const std::size_t at = comment.find(kPortEmptyComment);
  if (marks.read_late && at != std::string_view::npos) {
    const char* const first = comment.data() + at + kPortEmptyComment.size();
    const char* const last = comment.data() + comment.size();
    Nanos before = 0;
    const auto [next, error] = std::from_chars(first, last, before);
    if (error == std::errc{} && next != first && before >= 0 &&
        std::string_view(next, static_cast<std::size_t>(last - next))
            .starts_with(kPortEmptyCommentEnd)) {
      marks.quiet_before = before;
    }
  }
  return marks;
}

}  // namespace rtu
