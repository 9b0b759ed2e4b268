#include "capture/rtac_serial.hpp"

#include <fmt/format.h>

#include <array>

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

}  // namespace rtu
