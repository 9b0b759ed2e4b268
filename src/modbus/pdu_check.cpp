// check_pdu() and check_response_fits(): the rules of MODBUS Application Protocol V1.1b3
// §6 that a single frame, or a request with its response, can break.
#include <algorithm>

#include "core/function_codes.hpp"
#include "modbus/pdu.hpp"
#include "modbus/pdu_names.hpp"

namespace rtu {
namespace {

constexpr std::uint8_t kFirstReservedSlave = 248;  // Serial Line V1.02 §2.2

void require(IssueSet& issues, bool ok, IssueId id) {
  if (!ok) issues.add(id);
}

bool in_range(unsigned v, unsigned lo, unsigned hi) {
  return v >= lo && v <= hi;
}

unsigned coil_bytes(unsigned qty) {
  return (qty + 7U) / 8U;
}

// Spec quantity limits (§6.1-§6.4, §6.11, §6.12, §6.17).
unsigned max_read_qty(std::uint8_t function) {
  return function == fc::kReadCoils || function == fc::kReadDiscreteInputs ? 2000U : 125U;
}
unsigned max_write_qty(std::uint8_t function) {
  return function == fc::kWriteMultipleCoils ? 1968U : 123U;
}

// A broadcast of a function that no broadcast may carry (may_be_broadcast), or of a
// diagnostics sub-function that does more than act (restart, delimiter, listen only, clear).
bool broadcast_useless(const DecodedPdu& pdu) {
  const PduHeader& h = pdu_header(pdu);
  if (h.function == fc::kDiagnostics) {
    if (const auto* d = std::get_if<DiagnosticsPdu>(&pdu)) {
      const std::uint16_t s = d->sub_function;
      return !(s == 0x01 || s == 0x03 || s == 0x04 || s == 0x0A || s == 0x14);
    }
    return true;
  }
  return !may_be_broadcast(h.function);
}

void check_fields(IssueSet& /*issues*/, const RawPdu& /*p*/) {}
void check_fields(IssueSet& /*issues*/, const ExceptionResponse& /*p*/) {}
void check_fields(IssueSet& /*issues*/, const NoDataRequest& /*p*/) {}
void check_fields(IssueSet& /*issues*/, const ExceptionStatusResponse& /*p*/) {}
void check_fields(IssueSet& /*issues*/, const CommEventCounterResponse& /*p*/) {}
void check_fields(IssueSet& /*issues*/, const ServerIdResponse& /*p*/) {}
void check_fields(IssueSet& /*issues*/, const MaskWrite& /*p*/) {}
void check_fields(IssueSet& /*issues*/, const FifoRequest& /*p*/) {}

void check_fields(IssueSet& issues, const ReadRequest& p) {
  require(issues, in_range(p.qty, 1, max_read_qty(p.function)), IssueId::kBadQuantity);
}

void check_fields(IssueSet& issues, const ReadBitsResponse& p) {
  require(issues, in_range(p.byte_count, 1, coil_bytes(2000)), IssueId::kByteCount);
}

void check_fields(IssueSet& issues, const ReadRegistersResponse& p) {
  const unsigned max_bytes = 2U * 125U;
  require(issues, in_range(p.byte_count, 2, max_bytes) && p.byte_count % 2 == 0,
          IssueId::kByteCount);
}

void check_fields(IssueSet& issues, const WriteSingle& p) {
  if (p.function == fc::kWriteSingleCoil) require(issues, p.coil().has_value(), IssueId::kBadValue);
}

void check_fields(IssueSet& issues, const WriteMultipleCoilsRequest& p) {
  require(issues, in_range(p.qty, 1, max_write_qty(p.function)), IssueId::kBadQuantity);
  require(issues, p.byte_count == coil_bytes(p.qty), IssueId::kByteCount);
}

void check_fields(IssueSet& issues, const WriteMultipleRegistersRequest& p) {
  require(issues, in_range(p.qty, 1, max_write_qty(p.function)), IssueId::kBadQuantity);
  require(issues, p.byte_count == 2U * p.qty, IssueId::kByteCount);
}

void check_fields(IssueSet& issues, const WriteMultipleResponse& p) {
  require(issues, in_range(p.qty, 1, max_write_qty(p.function)), IssueId::kBadQuantity);
}

void check_fields(IssueSet& issues, const DiagnosticsPdu& p) {
  require(issues, is_known_diagnostics_sub_function(p.sub_function), IssueId::kBadValue);
  // Restart Communications Option: data 0000 or FF00 (clear the event log) (§6.8.1).
  if (p.sub_function == 0x01 && p.payload.size() == 2) {
    const bool ok = (p.payload[0] == 0x00 || p.payload[0] == 0xFF) && p.payload[1] == 0x00;
    require(issues, ok, IssueId::kBadValue);
  }
}

void check_fields(IssueSet& issues, const CommEventLogResponse& p) {
  // Status, event count, message count (6 bytes) and 0-64 event bytes (§6.9).
  require(issues, in_range(p.byte_count, 6, 6 + 64), IssueId::kByteCount);
}

void check_file_records(IssueSet& issues, const FileRecordList& records, bool request) {
  for (const FileSubRecord& r : records) {
    if (!r.complete) continue;  // a partial item is already a byte count issue
    require(issues, r.ref_type == 6, IssueId::kBadValue);
    // File 0x0001-0xFFFF, record 0x0000-0x270F (§6.14).
    if (request) require(issues, r.file != 0 && r.record <= 0x270F, IssueId::kBadValue);
  }
}

void check_fields(IssueSet& issues, const FileRecordRequest& p) {
  const bool read = p.function == fc::kReadFileRecord;
  // Byte count 0x07-0xF5 for FC20, 0x09-0xFB for FC21 (§6.14, §6.15).
  require(issues, read ? in_range(p.byte_count, 0x07, 0xF5) : in_range(p.byte_count, 0x09, 0xFB),
          IssueId::kByteCount);
  check_file_records(issues, p.records, true);
}

void check_fields(IssueSet& issues, const ReadFileRecordResponse& p) {
  require(issues, in_range(p.byte_count, 0x07, 0xF5), IssueId::kByteCount);
  check_file_records(issues, p.records, false);
}

void check_fields(IssueSet& issues, const ReadWriteMultipleRequest& p) {
  // Read 1-125, write 1-121 (§6.17).
  require(issues, in_range(p.read_qty, 1, 125) && in_range(p.write_qty, 1, 121),
          IssueId::kBadQuantity);
  require(issues, p.byte_count == 2U * p.write_qty, IssueId::kByteCount);
}

void check_fields(IssueSet& issues, const FifoResponse& p) {
  require(issues, p.fifo_count <= 31, IssueId::kBadQuantity);  // §6.18
  require(issues, p.byte_count == 2U + 2U * p.fifo_count, IssueId::kByteCount);
}

void check_fields(IssueSet& issues, const DeviceIdRequest& p) {
  require(issues, in_range(p.read_device_id_code, 1, 4), IssueId::kBadValue);
}

void check_fields(IssueSet& issues, const DeviceIdResponse& p) {
  const std::uint8_t c = p.conformity;
  const bool conformity_ok = in_range(c & 0x7FU, 1, 3) && (c & 0x7CU) == 0;
  require(issues,
          in_range(p.read_device_id_code, 1, 4) && conformity_ok &&
              (p.more_follows == 0x00 || p.more_follows == 0xFF),
          IssueId::kBadValue);
}

void check_fields(IssueSet& issues, const MeiPdu& p) {
  // 0x0D (CANopen) and 0x0E are the only assigned MEI types (V1.1b3 Annex A).
  require(issues, p.mei == 0x0D, IssueId::kUnknownFunction);
}

bool same_bytes(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end());
}

// FC08 sub-functions whose response echoes the request data (§6.8.1); others return a
// counter or register.
bool diagnostics_echoes_data(std::uint16_t sub_function) {
  return sub_function == 0x00 || sub_function == 0x01 || sub_function == 0x03 ||
         sub_function == 0x04 || sub_function == 0x0A || sub_function == 0x14;
}

}  // namespace

IssueSet check_pdu(const DecodedPdu& pdu) {
  const PduHeader& h = pdu_header(pdu);
  IssueSet issues = h.issues;
  if (h.slave >= kFirstReservedSlave) issues.add(IssueId::kReservedAddress);
  // An exception response to any function code is a plain answer, not an unknown function.
  const bool exception = (h.function & fc::kExceptionBit) != 0 && h.role != Role::kRequest;
  if (!exception && !is_public_function(h.function)) issues.add(IssueId::kUnknownFunction);
  if (h.role == Role::kRequest && h.slave == 0 && broadcast_useless(pdu)) {
    issues.add(IssueId::kBroadcastRead);
  }
  std::visit([&issues](const auto& p) { check_fields(issues, p); }, pdu);
  return issues;
}

IssueSet check_response_fits(const Record& request, const Record& response) {
  if (response.is_exception() || request.function() != response.function()) return {};
  return check_response_fits(request, decode_pdu(request, Role::kRequest), response,
                             decode_pdu(response, Role::kResponse));
}

IssueSet check_response_fits(const Record& request, const DecodedPdu& req, const Record& response,
                             const DecodedPdu& rsp) {
  IssueSet issues;
  if (response.is_exception() || request.function() != response.function()) return issues;
  const PduHeader& rq = pdu_header(req);
  const PduHeader& rs = pdu_header(rsp);

  switch (request.function()) {
    case fc::kReadCoils:
    case fc::kReadDiscreteInputs:
      if (const auto* q = std::get_if<ReadRequest>(&req)) {
        if (const auto* r = std::get_if<ReadBitsResponse>(&rsp)) {
          require(issues, r->byte_count == coil_bytes(q->qty), IssueId::kByteCount);
        }
      }
      break;
    case fc::kReadHoldingRegisters:
    case fc::kReadInputRegisters:
      if (const auto* q = std::get_if<ReadRequest>(&req)) {
        if (const auto* r = std::get_if<ReadRegistersResponse>(&rsp)) {
          require(issues, r->byte_count == 2U * q->qty, IssueId::kByteCount);
        }
      }
      break;
    case fc::kReadWriteMultipleRegisters:
      if (const auto* q = std::get_if<ReadWriteMultipleRequest>(&req)) {
        if (const auto* r = std::get_if<ReadRegistersResponse>(&rsp)) {
          require(issues, r->byte_count == 2U * q->read_qty, IssueId::kByteCount);
        }
      }
      break;
    case fc::kWriteSingleCoil:
    case fc::kWriteSingleRegister:
    case fc::kMaskWriteRegister:
    case fc::kWriteFileRecord:
      // The response is a byte-for-byte echo of the request (§6.5, §6.6, §6.15, §6.16).
      require(issues, same_bytes(rq.data, rs.data), IssueId::kEchoMismatch);
      break;
    case fc::kDiagnostics:
      if (const auto* q = std::get_if<DiagnosticsPdu>(&req)) {
        if (const auto* r = std::get_if<DiagnosticsPdu>(&rsp)) {
          const bool echo_ok =
              q->sub_function == r->sub_function &&
              (!diagnostics_echoes_data(q->sub_function) || same_bytes(q->payload, r->payload));
          require(issues, echo_ok, IssueId::kEchoMismatch);
        }
      }
      break;
    case fc::kWriteMultipleCoils:
    case fc::kWriteMultipleRegisters: {
      const auto* r = std::get_if<WriteMultipleResponse>(&rsp);
      if (r == nullptr) break;
      if (const auto* q = std::get_if<WriteMultipleCoilsRequest>(&req)) {
        require(issues, q->addr == r->addr && q->qty == r->qty, IssueId::kAddressMismatch);
      } else if (const auto* w = std::get_if<WriteMultipleRegistersRequest>(&req)) {
        require(issues, w->addr == r->addr && w->qty == r->qty, IssueId::kAddressMismatch);
      }
      break;
    }
    case fc::kReadFileRecord:
      if (const auto* q = std::get_if<FileRecordRequest>(&req)) {
        if (const auto* r = std::get_if<ReadFileRecordResponse>(&rsp)) {
          // One sub-response per sub-request, each 1 + 2 × record_length bytes (§6.14).
          bool fits = q->records.count() == r->records.count();
          auto qi = q->records.begin();
          for (auto ri = r->records.begin(); fits && ri != r->records.end(); ++ri, ++qi) {
            fits = ri->resp_length == 1U + 2U * qi->record_length;
          }
          require(issues, fits, IssueId::kByteCount);
        }
      }
      break;
    case fc::kEncapsulatedInterface: {
      // The MEI type, and for 0x0E the read device id code, come back as sent (§6.19).
      bool echo_ok = rq.data.empty() || rs.data.empty() || rq.data[0] == rs.data[0];
      if (const auto* q = std::get_if<DeviceIdRequest>(&req)) {
        if (const auto* r = std::get_if<DeviceIdResponse>(&rsp)) {
          echo_ok = echo_ok && q->read_device_id_code == r->read_device_id_code;
        }
      }
      require(issues, echo_ok, IssueId::kEchoMismatch);
      break;
    }
    default: break;
  }
  return issues;
}

}  // namespace rtu
