#pragma once
// Records of LINKTYPE_RTAC_SERIAL (250): a 12-byte big-endian header (seconds, µs, event
// type, UART control lines, reserved footer), then the bytes (tcpdump.org/linktypes/
// LINKTYPE_RTAC_SERIAL.html). rtuscope writes raw read() chunks and line events with it.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/chunk.hpp"
#include "core/time.hpp"

namespace rtu {

inline constexpr std::size_t kRtacHeaderSize = 12;
inline constexpr std::size_t kRtacEventOffset = 8;  // the event type's byte in the header

// What a read's time is not evidence of travels as a comment (opt_comment) on its first
// data record, written by a live recording and a raw export: Wireshark shows it, and a
// reader takes the mark back from it, so the read decodes the same again.
// Chunk::read_late:
inline constexpr std::string_view kReadLateComment =
    "read late: the host took longer than the timing resolution to read these bytes, so "
    "the silences before and after them are not evidence";
// Chunk::time_clamped:
inline constexpr std::string_view kTimeClampedComment =
    "time clamped: the input's time went back here, so how long after the read before this "
    "one came is not known";

// Chunk::quiet_until of a late read, as how long before its record's time: "port empty "
// then that many ns, then kPortEmptyCommentEnd.
inline constexpr std::string_view kPortEmptyComment = "port empty ";
inline constexpr std::string_view kPortEmptyCommentEnd =
    " ns before this read: the line was quiet up to then";

struct ReadTimeMarks {
  bool read_late = false;
  bool time_clamped = false;
  Nanos quiet_before = kUnknownTime;  // see kPortEmptyComment
};
// The marks of `chunk`, written on a record of time `record_time`.
ReadTimeMarks time_marks_of(const Chunk& chunk, Nanos record_time);
// The comment for `marks`, empty for none (one line each).
std::string time_marks_comment(ReadTimeMarks marks);
// The marks a record's comment (its comments joined by newlines) carries.
ReadTimeMarks time_marks_of(std::string_view comment);

// Event types, with the names Wireshark shows.
enum class RtacEvent : std::uint8_t {
  kStatusChange = 0x00,
  kDataTxStart = 0x01,  // rtuscope: bytes sent by the master (when known)
  kDataRxStart = 0x02,  // rtuscope: bytes received (the default for sniffed chunks)
  kDataTxEnd = 0x03,
  kDataRxEnd = 0x04,
  kCaptureDataLost = 0x05,
  kCaptureComplete = 0x06,
  kFramingError = 0x07,
  kParityError = 0x08,
  kSerialBreak = 0x09,
  kSerialOverflow = 0x0A,
};

// UART control line bits of header byte 9.
namespace rtac_lines {
inline constexpr std::uint8_t kCts = 0x01;
inline constexpr std::uint8_t kDcd = 0x02;
inline constexpr std::uint8_t kDsr = 0x04;
inline constexpr std::uint8_t kRts = 0x08;
inline constexpr std::uint8_t kDtr = 0x10;
inline constexpr std::uint8_t kRing = 0x20;
inline constexpr std::uint8_t kMbok = 0x40;
}  // namespace rtac_lines

// "PARITY_ERROR"; "UNKNOWN" for codes past 0x0A.
std::string_view rtac_event_name(std::uint8_t event);

// Replaces `out` with header + payload. `t` ≥ 0, ns since 1970 (stored as s + µs).
void build_rtac_record(Nanos t, RtacEvent event, std::uint8_t control_lines,
                       std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& out);

struct RtacRecord {
  std::uint32_t seconds = 0;
  std::uint32_t micros = 0;
  std::uint8_t event = 0;  // RtacEvent value (kept raw: files may hold unknown codes)
  std::uint8_t control_lines = 0;
  std::uint16_t footer = 0;
  std::span<const std::uint8_t> payload;  // view into the parsed record

  [[nodiscard]] Nanos header_time() const {
    return static_cast<Nanos>(seconds) * kNanosPerSecond + static_cast<Nanos>(micros) * 1000;
  }
};

// nullopt (and `error`) when the record is shorter than its header.
std::optional<RtacRecord> parse_rtac_record(std::span<const std::uint8_t> record,
                                            std::string& error);

}  // namespace rtu
