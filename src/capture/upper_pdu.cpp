#include "capture/upper_pdu.hpp"

#include <fmt/format.h>

#include <array>
#include <cstring>

#include "capture/byte_order.hpp"
#include "capture/field_cursor.hpp"

namespace rtu {
namespace {

// Strings carry at least one NUL, then pad to a multiple of 4 (as Wireshark's exporter).
std::size_t padded_text(std::string_view text) {
  return (text.size() + 4U) & ~std::size_t{3};
}

// Writes tags one after the other into a record sized beforehand (FieldCursor). Tag values
// are big-endian and their length field states the padded length.
class TagWriter {
 public:
  explicit TagWriter(std::uint8_t* at) : cursor_(at, ByteOrder::kBig) {}

  void tag(std::uint16_t tag, std::span<const std::uint8_t> value, std::size_t padded_length) {
    cursor_.tlv(tag, static_cast<std::uint16_t>(padded_length), value, padded_length);
  }
  void text(std::uint16_t tag_id, std::string_view text) {
    tag(tag_id, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()),
        padded_text(text));
  }
  void u32(std::uint16_t tag_id, std::uint32_t value) {
    std::array<std::uint8_t, 4> bytes{};
    put(bytes.data(), value, ByteOrder::kBig);
    tag(tag_id, bytes, 4);
  }
  void bytes(std::span<const std::uint8_t> data) { cursor_.bytes(data, data.size()); }

 private:
  FieldCursor cursor_;
};

std::string_view as_text(std::span<const std::uint8_t> value) {
  std::string_view text(reinterpret_cast<const char*>(value.data()), value.size());
  while (!text.empty() && text.back() == '\0') text.remove_suffix(1);
  return text;
}

}  // namespace

void build_upper_pdu(std::span<const std::uint8_t> payload, const UpperPduBuild& options,
                     std::vector<std::uint8_t>& out) {
  const bool ports = options.direction != PduDirection::kUnknown;
  const bool column = !options.protocol_column.empty();
  out.resize(4 + padded_text(options.dissector) + (ports ? 3 * 8 : 0) +
             (column ? 4 + padded_text(options.protocol_column) : 0) + 4 + payload.size());
  TagWriter w(out.data());
  w.text(upper_pdu::kTagDissectorName, options.dissector);
  if (ports) {
    const bool request = options.direction == PduDirection::kRequest;
    w.u32(upper_pdu::kTagPortType, upper_pdu::kPortTypeTcp);
    w.u32(upper_pdu::kTagSourcePort, request ? upper_pdu::kMasterPort : upper_pdu::kSlavePort);
    w.u32(upper_pdu::kTagDestinationPort, request ? upper_pdu::kSlavePort : upper_pdu::kMasterPort);
  }
  if (column) w.text(upper_pdu::kTagProtocolColumn, options.protocol_column);
  w.tag(upper_pdu::kTagEndOfOptions, {}, 0);
  w.bytes(payload);
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

bool parse_upper_pdu(std::span<const std::uint8_t> record, UpperPdu& pdu, std::string& error) {
  pdu = UpperPdu{};
  std::size_t pos = 0;
  for (;;) {
    if (record.size() - pos < 4) {
      error = fmt::format(
          "byte {}: TLV header cut off ({} bytes left); expected a tag and a "
          "length, ending with tag 0",
          pos, record.size() - pos);
      return false;
    }
    const std::uint16_t tag = load_u16(record, pos, ByteOrder::kBig);
    const std::uint16_t length = load_u16(record, pos + 2, ByteOrder::kBig);
    if (length > record.size() - pos - 4) {
      error = fmt::format("byte {}: tag {} of length {} runs past the end of the record", pos, tag,
                          length);
      return false;
    }
    const auto value = record.subspan(pos + 4, length);
    pos += 4 + length;
    const auto u32 = [&]() -> std::optional<std::uint32_t> {
      if (value.size() != 4) return std::nullopt;
      return load_u32(value, 0, ByteOrder::kBig);
    };
    switch (tag) {
      case upper_pdu::kTagEndOfOptions: pdu.payload = record.subspan(pos); return true;
      case upper_pdu::kTagDissectorName: pdu.dissector = as_text(value); break;
      case upper_pdu::kTagPortType: pdu.port_type = u32(); break;
      case upper_pdu::kTagSourcePort: pdu.source_port = u32(); break;
      case upper_pdu::kTagDestinationPort: pdu.destination_port = u32(); break;
      case upper_pdu::kTagProtocolColumn: pdu.protocol_column = as_text(value); break;
      default: break;  // addresses, frame numbers …: not needed
    }
  }
}

bool UpperPduReader::parse(std::span<const std::uint8_t> record, UpperPdu& pdu,
                           std::string& error) {
  for (const Header& known : headers_) {
    if (known.size != 0 && record.size() >= known.size &&
        std::memcmp(record.data(), known.bytes.data(), known.size) == 0) {
      pdu = known.pdu;
      pdu.payload = record.subspan(known.size);
      return true;
    }
  }
  if (!parse_upper_pdu(record, pdu, error)) return false;
  remember(record, pdu);
  return true;
}

void UpperPduReader::remember(std::span<const std::uint8_t> record, const UpperPdu& pdu) {
  const std::size_t size = record.size() - pdu.payload.size();
  if (size == 0 || size > kMaxRemembered) return;
  Header& header = headers_[replace_next_];
  replace_next_ = (replace_next_ + 1) % headers_.size();
  std::memcpy(header.bytes.data(), record.data(), size);
  header.size = size;
  header.pdu = pdu;
  header.pdu.payload = {};
  // The texts are views into the header: moved to the copy.
  const auto moved = [&](std::string_view text) {
    if (text.empty()) return text;
    const auto at = static_cast<std::size_t>(reinterpret_cast<const std::uint8_t*>(text.data()) -
                                             record.data());
    return std::string_view(reinterpret_cast<const char*>(header.bytes.data() + at), text.size());
  };
  header.pdu.dissector = moved(pdu.dissector);
  header.pdu.protocol_column = moved(pdu.protocol_column);
}

bool mbrtu_declines(std::span<const std::uint8_t> adu) {
  return adu.size() < 5 || adu[0] == 0;
}

}  // namespace rtu
