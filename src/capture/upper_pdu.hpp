#pragma once
// Records of LINKTYPE_WIRESHARK_UPPER_PDU (252): big-endian TLVs, an end tag, then the
// payload (wsutil/exported_pdu_tlvs.h). rtuscope puts one Modbus RTU ADU (CRC included) in
// each record for Wireshark's `mbrtu` dissector.
//
// Direction: Wireshark's Modbus RTU dissector can only classify a frame as query or
// response from its length for a few function codes. The records therefore carry TCP-style
// ports, requests 1 → 502 and responses 502 → 1; opened with `-o mbrtu.tcp.port:502`,
// every function code (echoes of FC05/06/08 included) is classified, decoded and paired.
// Frames whose role is unknown carry no ports and Wireshark guesses.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rtu {

namespace upper_pdu {
inline constexpr std::uint16_t kTagEndOfOptions = 0;
inline constexpr std::uint16_t kTagDissectorName = 12;
inline constexpr std::uint16_t kTagPortType = 24;
inline constexpr std::uint16_t kTagSourcePort = 25;
inline constexpr std::uint16_t kTagDestinationPort = 26;
inline constexpr std::uint16_t kTagProtocolColumn = 33;
inline constexpr std::uint32_t kPortTypeTcp = 2;
inline constexpr std::uint32_t kMasterPort = 1;
inline constexpr std::uint32_t kSlavePort = 502;
inline constexpr std::string_view kModbusRtuDissector = "mbrtu";
}  // namespace upper_pdu

enum class PduDirection : std::uint8_t { kUnknown, kRequest, kResponse };

struct UpperPduBuild {
  std::string_view dissector = upper_pdu::kModbusRtuDissector;
  PduDirection direction = PduDirection::kUnknown;
  // COL_PROT_TEXT: labels the Protocol column even where the dissector declines the
  // payload (unit 0, frames under 5 bytes). Omitted when empty.
  std::string_view protocol_column;
};

// Replaces `out` with a record carrying `payload`. Strings are NUL-padded to 4 bytes, as
// Wireshark's own exporter writes them.
void build_upper_pdu(std::span<const std::uint8_t> payload, const UpperPduBuild& options,
                     std::vector<std::uint8_t>& out);

struct UpperPdu {
  std::string_view dissector;  // trailing NULs removed; empty when absent
  std::optional<std::uint32_t> port_type;
  std::optional<std::uint32_t> source_port;
  std::optional<std::uint32_t> destination_port;
  std::string_view protocol_column;
  std::span<const std::uint8_t> payload;  // view into the parsed record

  // From the ports by the convention above; kUnknown when they do not say.
  [[nodiscard]] PduDirection direction() const;
};

// Parses a record into `pdu` (views into `record`). On malformed TLVs returns false and sets
// `error` to what was expected and at which byte of the record. (Filled in place: a returned
// std::optional<UpperPdu> was built on the stack and reloaded in other widths than it was
// stored in, which stalled the reading of every record.)
bool parse_upper_pdu(std::span<const std::uint8_t> record, UpperPdu& pdu, std::string& error);

// parse_upper_pdu() for a file's records one after the other. A writer repeats a few
// headers (the TLVs before the payload: one for requests, one for answers in rtuscope's
// recordings), and a header met in the last two records is only compared, not parsed again:
// the parse depends on nothing but those bytes. Same answers as parse_upper_pdu(), except
// that the views of a remembered header (dissector, protocol_column) point into this
// object and hold until the next call.
class UpperPduReader {
 public:
  bool parse(std::span<const std::uint8_t> record, UpperPdu& pdu, std::string& error);

 private:
  // Longer headers are parsed every time (rtuscope's are 40 bytes, Wireshark's about as long).
  static constexpr std::size_t kMaxRemembered = 64;
  struct Header {
    std::array<std::uint8_t, kMaxRemembered> bytes{};
    std::size_t size = 0;  // 0: none remembered yet
    UpperPdu pdu;          // its parse; the views into `bytes`, payload empty
  };
  void remember(std::span<const std::uint8_t> record, const UpperPdu& pdu);
  std::array<Header, 2> headers_;
  std::size_t replace_next_ = 0;
};

// True when Wireshark's mbrtu dissector declines this ADU (it then shows as Data):
// broadcast frames (unit 0) and frames shorter than 5 bytes.
bool mbrtu_declines(std::span<const std::uint8_t> adu);

}  // namespace rtu
