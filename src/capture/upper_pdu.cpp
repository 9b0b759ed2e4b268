#include "capture/upper_pdu.hpp"

#include <fmt/format.h>

#include <array>

#include "capture/byte_order.hpp"

namespace rtu {
namespace {

void add_tag(std::vector<std::uint8_t>& out, std::uint16_t tag, std::span<const std::uint8_t> value,
             std::size_t padded_length) {
  append<std::uint16_t>(out, tag, ByteOrder::kBig);
  append<std::uint16_t>(out, static_cast<std::uint16_t>(padded_length), ByteOrder::kBig);
  out.insert(out.end(), value.begin(), value.end());
  out.resize(out.size() + (padded_length - value.size()), 0);
}

void add_text(std::vector<std::uint8_t>& out, std::uint16_t tag, std::string_view text) {
  const std::span bytes(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  // At least one NUL, then up to a multiple of 4 (Wireshark's exporter does the same).
  add_tag(out, tag, bytes, (text.size() + 4U) & ~std::size_t{3});
}

void add_u32(std::vector<std::uint8_t>& out, std::uint16_t tag, std::uint32_t value) {
  std::array<std::uint8_t, 4> bytes{};
  put(bytes.data(), value, ByteOrder::kBig);
  add_tag(out, tag, bytes, 4);
}

std::string_view as_text(std::span<const std::uint8_t> value) {
  std::string_view text(reinterpret_cast<const char*>(value.data()), value.size());
  while (!text.empty() && text.back() == '\0') text.remove_suffix(1);
  return text;
}

}  // namespace

void build_upper_pdu(std::span<const std::uint8_t> payload, const UpperPduBuild& options,
                     std::vector<std::uint8_t>& out) {
  out.clear();
  add_text(out, upper_pdu::kTagDissectorName, options.dissector);
  if (options.direction != PduDirection::kUnknown) {
    const bool request = options.direction == PduDirection::kRequest;
    add_u32(out, upper_pdu::kTagPortType, upper_pdu::kPortTypeTcp);
    add_u32(out, upper_pdu::kTagSourcePort,
            request ? upper_pdu::kMasterPort : upper_pdu::kSlavePort);
    add_u32(out, upper_pdu::kTagDestinationPort,
            request ? upper_pdu::kSlavePort : upper_pdu::kMasterPort);
  }
  if (!options.protocol_column.empty()) {
    add_text(out, upper_pdu::kTagProtocolColumn, options.protocol_column);
  }
  append<std::uint16_t>(out, upper_pdu::kTagEndOfOptions, ByteOrder::kBig);
  append<std::uint16_t>(out, 0, ByteOrder::kBig);
  out.insert(out.end(), payload.begin(), payload.end());
}

PduDirection UpperPdu::direction() const {
  if (!source_port || !destination_port) return PduDirection::kUnknown;
  if (*destination_port == upper_pdu::kSlavePort && *source_port != upper_pdu::kSlavePort) {
    return PduDirection::kRequest;
  }
  if (*source_port == upper_pdu::kSlavePort && *destination_port != upper_pdu::kSlavePort) {
    return PduDirection::kResponse;
  }
  return PduDirection::kUnknown;
}

std::optional<UpperPdu> parse_upper_pdu(std::span<const std::uint8_t> record, std::string& error) {
  UpperPdu pdu;
  std::size_t pos = 0;
  for (;;) {
    if (record.size() - pos < 4) {
      error = fmt::format(
          "byte {}: TLV header cut off ({} bytes left); expected a tag and a "
          "length, ending with tag 0",
          pos, record.size() - pos);
      return std::nullopt;
    }
    const std::uint16_t tag = load_u16(record, pos, ByteOrder::kBig);
    const std::uint16_t length = load_u16(record, pos + 2, ByteOrder::kBig);
    if (length > record.size() - pos - 4) {
      error = fmt::format("byte {}: tag {} of length {} runs past the end of the record", pos, tag,
                          length);
      return std::nullopt;
    }
    const auto value = record.subspan(pos + 4, length);
    pos += 4 + length;
    const auto u32 = [&]() -> std::optional<std::uint32_t> {
      if (value.size() != 4) return std::nullopt;
      return load_u32(value, 0, ByteOrder::kBig);
    };
    switch (tag) {
      case upper_pdu::kTagEndOfOptions: pdu.payload = record.subspan(pos); return pdu;
      case upper_pdu::kTagDissectorName: pdu.dissector = as_text(value); break;
      case upper_pdu::kTagPortType: pdu.port_type = u32(); break;
      case upper_pdu::kTagSourcePort: pdu.source_port = u32(); break;
      case upper_pdu::kTagDestinationPort: pdu.destination_port = u32(); break;
      case upper_pdu::kTagProtocolColumn: pdu.protocol_column = as_text(value); break;
      default: break;  // addresses, frame numbers …: not needed
    }
  }
}

bool mbrtu_declines(std::span<const std::uint8_t> adu) {
  return adu.size() < 5 || adu[0] == 0;
}

}  // namespace rtu
