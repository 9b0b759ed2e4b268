#pragma once
// Typed, allocation-free decode of a Modbus PDU (MODBUS Application Protocol V1.1b3 §6, §7).
//
// decode_pdu() turns one frame into one of the structs below, held in DecodedPdu. Every
// struct derives from PduHeader and holds plain fields plus views (spans) into the
// Record's bytes: a DecodedPdu is valid only as long as the Record it came from (and, for
// a response, its request) is alive and unchanged. Nothing here allocates.
//
// Malformed frames are data: the decoder never reads outside the frame, decodes what is
// there, and notes structural problems in PduHeader::issues (kTruncated, kByteCount,
// kExtraBytes). check_pdu() adds the rules of the specification (quantities, values,
// addresses); check_response_fits() compares a response with its request.
#include <fmt/format.h>

#include <cstdint>
#include <optional>
#include <span>
#include <variant>

#include "core/issue.hpp"
#include "framing/record.hpp"
#include "modbus/pdu_views.hpp"

namespace rtu {

class JsonWriter;

// Common to every decoded PDU.
struct PduHeader {
  std::uint8_t slave = 0;
  std::uint8_t function = 0;   // as on the wire, exception bit included
  Role role = Role::kUnknown;  // the role the PDU was decoded as
  IssueSet issues;             // structural problems found while decoding
  // PDU bytes after the function code, CRC excluded (the last two bytes of the frame are
  // taken as the CRC whatever their value).
  std::span<const std::uint8_t> data{};
};

// A PDU this decoder cannot give fields to: a non-public function code, a public one in a
// role it cannot have (request with the exception bit), an unknown role, or a frame too
// short for its function's fixed fields (then issues has kTruncated). `data` is the payload.
struct RawPdu : PduHeader {};

// FC | 0x80, one exception code (§7).
struct ExceptionResponse : PduHeader {
  std::uint8_t code = 0;
};

// FC01-04 request.
struct ReadRequest : PduHeader {
  std::uint16_t addr = 0;
  std::uint16_t qty = 0;
};

// FC01/02 response. `bits` is trimmed to the request's quantity when it is known.
struct ReadBitsResponse : PduHeader {
  std::uint8_t byte_count = 0;
  BitView bits{};
  std::optional<std::uint16_t> addr{};  // from the request
  std::optional<std::uint16_t> qty{};   // from the request
};

// FC03/04 response, and FC23 response (then addr/qty are the request's read part).
struct ReadRegistersResponse : PduHeader {
  std::uint8_t byte_count = 0;
  WordView values{};
  std::optional<std::uint16_t> addr{};  // from the request
  std::optional<std::uint16_t> qty{};   // from the request
};

// FC05 / FC06, request and its echo.
struct WriteSingle : PduHeader {
  std::uint16_t addr = 0;
  std::uint16_t value = 0;
  // FC05 only: FF00 = on, 0000 = off, anything else invalid.
  [[nodiscard]] std::optional<bool> coil() const {
    if (value == 0xFF00) return true;
    if (value == 0x0000) return false;
    return std::nullopt;
  }
};

// FC15 request.
struct WriteMultipleCoilsRequest : PduHeader {
  std::uint16_t addr = 0;
  std::uint16_t qty = 0;
  std::uint8_t byte_count = 0;
  BitView coils{};  // qty bits, clipped to the data present
};

// FC16 request.
struct WriteMultipleRegistersRequest : PduHeader {
  std::uint16_t addr = 0;
  std::uint16_t qty = 0;
  std::uint8_t byte_count = 0;
  WordView values{};  // the words the byte count covers, clipped to the data present
};

// FC15 / FC16 response.
struct WriteMultipleResponse : PduHeader {
  std::uint16_t addr = 0;
  std::uint16_t qty = 0;
};

// FC07, FC11, FC12, FC17 requests: the function code alone.
struct NoDataRequest : PduHeader {};

// FC07 response.
struct ExceptionStatusResponse : PduHeader {
  std::uint8_t status = 0;
};

// FC08, either role: sub-function and its data (echoed, or a counter in the response).
struct DiagnosticsPdu : PduHeader {
  std::uint16_t sub_function = 0;
  std::span<const std::uint8_t> payload{};  // after the sub-function
};

// FC11 response.
struct CommEventCounterResponse : PduHeader {
  std::uint16_t status = 0;
  std::uint16_t event_count = 0;
};

// FC12 response.
struct CommEventLogResponse : PduHeader {
  std::uint8_t byte_count = 0;
  std::uint16_t status = 0;
  std::uint16_t event_count = 0;
  std::uint16_t message_count = 0;
  std::span<const std::uint8_t> events{};  // newest first, one byte each
};

// FC17 response. The server id and run indicator layout is device specific: raw bytes.
struct ServerIdResponse : PduHeader {
  std::uint8_t byte_count = 0;
  std::span<const std::uint8_t> payload{};
};

// FC20 request (Layout::kReadRequest), FC21 request and response (kWriteRequest).
struct FileRecordRequest : PduHeader {
  std::uint8_t byte_count = 0;
  FileRecordList records{};
};

// FC20 response (Layout::kReadResponse).
struct ReadFileRecordResponse : PduHeader {
  std::uint8_t byte_count = 0;
  FileRecordList records{};
};

// FC22, request and its echo. Result = (current AND and_mask) OR (or_mask AND NOT and_mask).
struct MaskWrite : PduHeader {
  std::uint16_t addr = 0;
  std::uint16_t and_mask = 0;
  std::uint16_t or_mask = 0;
};

// FC23 request.
struct ReadWriteMultipleRequest : PduHeader {
  std::uint16_t read_addr = 0;
  std::uint16_t read_qty = 0;
  std::uint16_t write_addr = 0;
  std::uint16_t write_qty = 0;
  std::uint8_t byte_count = 0;
  WordView values{};  // written values, clipped to the data present
};

// FC24 request.
struct FifoRequest : PduHeader {
  std::uint16_t addr = 0;
};

// FC24 response.
struct FifoResponse : PduHeader {
  std::uint16_t byte_count = 0;  // 2 bytes on the wire: counts fifo_count and the values
  std::uint16_t fifo_count = 0;
  WordView values{};
};

// FC43 / MEI 0x0E request.
struct DeviceIdRequest : PduHeader {
  std::uint8_t mei = 0;
  std::uint8_t read_device_id_code = 0;  // 1 basic, 2 regular, 3 extended, 4 one object
  std::uint8_t object_id = 0;
};

// FC43 / MEI 0x0E response.
struct DeviceIdResponse : PduHeader {
  std::uint8_t mei = 0;
  std::uint8_t read_device_id_code = 0;
  std::uint8_t conformity = 0;
  std::uint8_t more_follows = 0;  // 0x00 no, 0xFF yes
  std::uint8_t next_object_id = 0;
  std::uint8_t object_count = 0;  // as declared
  DeviceIdObjectList objects{};
};

// FC43 with any other MEI type (0x0D CANopen, reserved ones): the MEI type and raw data.
struct MeiPdu : PduHeader {
  std::uint8_t mei = 0;
  std::span<const std::uint8_t> payload{};
};

using DecodedPdu =
    std::variant<RawPdu, ExceptionResponse, ReadRequest, ReadBitsResponse, ReadRegistersResponse,
                 WriteSingle, WriteMultipleCoilsRequest, WriteMultipleRegistersRequest,
                 WriteMultipleResponse, NoDataRequest, ExceptionStatusResponse, DiagnosticsPdu,
                 CommEventCounterResponse, CommEventLogResponse, ServerIdResponse,
                 FileRecordRequest, ReadFileRecordResponse, MaskWrite, ReadWriteMultipleRequest,
                 FifoRequest, FifoResponse, DeviceIdRequest, DeviceIdResponse, MeiPdu>;

// A frame's decoding as the tracker made it, handed to the stages after it (Record::pdu),
// so that none decodes the frame again. A struct, so that record.hpp can declare it.
struct FramePdu {
  DecodedPdu pdu;
};

// The fields every alternative shares.
const PduHeader& pdu_header(const DecodedPdu& pdu);

// Decodes `frame` as `role` (decided by the caller). A response with frame.request set
// takes context from it (start address and quantity of a read). Role::kUnknown decodes
// exception responses and leaves everything else raw.
DecodedPdu decode_pdu(const Record& frame, Role role);

// The tracker's decoding of the frame (Record::pdu) where it made one in `role`, else null.
inline const DecodedPdu* tracker_decoding(const Record& frame, Role role) {
  return frame.pdu != nullptr && frame.role == role ? &frame.pdu->pdu : nullptr;
}
// The frame decoded as `role`: tracker_decoding() where there is one, else decode_pdu() into
// `scratch`. Valid while the frame (and `scratch`) is. `scratch` is built only when needed:
// this is asked for every frame a writer writes.
inline const DecodedPdu& decoding_of(const Record& frame, Role role,
                                     std::optional<DecodedPdu>& scratch) {
  if (const DecodedPdu* decoded = tracker_decoding(frame, role)) return *decoded;
  return scratch.emplace(decode_pdu(frame, role));
}

// Writes the decoded fields as keys into the frame's already-open JSON object. The keys are
// listed in pdu_json.cpp; they are public and stable.
void write_pdu_json(JsonWriter& json, const DecodedPdu& pdu);

// One short readable line, e.g. "read holding 0x0032 ×3" or "→ 3 regs 0xEA60 0xC350 0xDB6C".
void append_pdu_summary(fmt::memory_buffer& out, const DecodedPdu& pdu);

// Single-frame checks: the decode issues plus quantity ranges (kBadQuantity), byte counts
// (kByteCount), field values (kBadValue), broadcast of a read (kBroadcastRead), reserved
// slave address (kReservedAddress), non-public function code (kUnknownFunction).
IssueSet check_pdu(const DecodedPdu& pdu);

// Checks a response against its request (same slave and function assumed; an exception or
// another function code yields no issue here, the transaction tracker reports those):
// byte count vs quantity (kByteCount), echo differs for FC05/06/08/21/22 and MEI (kEchoMismatch),
// FC15/16 start address or quantity differ (kAddressMismatch).
IssueSet check_response_fits(const Record& request, const Record& response);
// The same, with both already decoded (decode_pdu(request, Role::kRequest) and
// decode_pdu(response, Role::kResponse)).
IssueSet check_response_fits(const Record& request, const DecodedPdu& decoded_request,
                             const Record& response, const DecodedPdu& decoded_response);

}  // namespace rtu
