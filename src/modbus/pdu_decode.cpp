// decode_pdu(): frame bytes → typed PDU (MODBUS Application Protocol V1.1b3 §6, §7).
// Every read goes through ByteCursor, so no byte count, however wrong, can move a read
// outside the frame. Fixed fields that are missing make the PDU raw (kTruncated);
// variable data that disagrees with its byte count is decoded as far as present
// (kByteCount).
#include <algorithm>

#include "core/byte_cursor.hpp"
#include "core/function_codes.hpp"
#include "modbus/pdu.hpp"

namespace rtu {
namespace {

using Bytes = std::span<const std::uint8_t>;

PduHeader make_header(const Record& frame, Role role) {
  PduHeader h;
  h.slave = frame.slave();
  h.function = frame.function();
  h.role = role;
  const Bytes bytes = frame.bytes();
  // address + function + ... + CRC(2): fewer than 4 bytes cannot be a whole ADU.
  if (bytes.size() >= 4) {
    h.data = bytes.subspan(2, bytes.size() - 4);
  } else {
    h.issues.add(IssueId::kTruncated);
  }
  return h;
}

RawPdu raw(const PduHeader& h) {
  return RawPdu{h};
}

RawPdu truncated(const PduHeader& h) {
  RawPdu pdu{h};
  pdu.issues.add(IssueId::kTruncated);
  return pdu;
}

// After a fixed layout: missing bytes → raw and truncated; spare bytes → kExtraBytes.
template <typename T>
DecodedPdu finish_fixed(T pdu, const ByteCursor& cur) {
  if (!cur.ok()) return truncated(pdu);
  if (!cur.at_end()) pdu.issues.add(IssueId::kExtraBytes);
  return pdu;
}

// The bytes a byte count announces, clipped to those present; notes a mismatch.
Bytes counted(PduHeader& h, Bytes rest, std::size_t byte_count) {
  if (rest.size() != byte_count) h.issues.add(IssueId::kByteCount);
  return rest.first(std::min(rest.size(), byte_count));
}

// Start address and quantity of the read this response answers, when its request is
// known and asks for the same function. FC23's read part sits where FC03's fields do.
struct ReadContext {
  std::optional<std::uint16_t> addr;
  std::optional<std::uint16_t> qty;
};

ReadContext read_context(const Record& response) {
  const Record* request = response.request;
  if (request == nullptr || request->function() != response.function()) return {};
  const Bytes bytes = request->bytes();
  if (bytes.size() < 8) return {};  // addr fc start(2) qty(2) crc(2)
  ByteCursor cur(bytes.subspan(2));
  ReadContext ctx;
  ctx.addr = cur.u16();
  ctx.qty = cur.u16();
  return ctx;
}

DecodedPdu decode_diagnostics(const PduHeader& h, ByteCursor& cur) {
  DiagnosticsPdu pdu{h};
  pdu.sub_function = cur.u16();
  if (!cur.ok()) return truncated(h);
  pdu.payload = cur.rest();
  // Sub-function 00 echoes any amount of data; every other one carries one word (§6.8).
  if (pdu.sub_function != 0x0000) {
    if (pdu.payload.size() < 2) pdu.issues.add(IssueId::kTruncated);
    if (pdu.payload.size() > 2) pdu.issues.add(IssueId::kExtraBytes);
  }
  return pdu;
}

DecodedPdu decode_file_records(const PduHeader& h, ByteCursor& cur, FileRecordList::Layout layout) {
  const std::uint8_t byte_count = cur.u8();
  if (!cur.ok()) return truncated(h);
  PduHeader header = h;
  const Bytes body = counted(header, cur.rest(), byte_count);
  const FileRecordList records(body, layout);
  if (!records.well_formed()) header.issues.add(IssueId::kByteCount);
  if (layout == FileRecordList::Layout::kReadResponse) {
    ReadFileRecordResponse pdu{header};
    pdu.byte_count = byte_count;
    pdu.records = records;
    return pdu;
  }
  FileRecordRequest pdu{header};
  pdu.byte_count = byte_count;
  pdu.records = records;
  return pdu;
}

DecodedPdu decode_request(const PduHeader& h) {
  ByteCursor cur(h.data);
  switch (h.function) {
    case fc::kReadCoils:
    case fc::kReadDiscreteInputs:
    case fc::kReadHoldingRegisters:
    case fc::kReadInputRegisters: {
      ReadRequest pdu{h};
      pdu.addr = cur.u16();
      pdu.qty = cur.u16();
      return finish_fixed(pdu, cur);
    }
    case fc::kWriteSingleCoil:
    case fc::kWriteSingleRegister: {
      WriteSingle pdu{h};
      pdu.addr = cur.u16();
      pdu.value = cur.u16();
      return finish_fixed(pdu, cur);
    }
    case fc::kReadExceptionStatus:
    case fc::kGetCommEventCounter:
    case fc::kGetCommEventLog:
    case fc::kReportServerId: return finish_fixed(NoDataRequest{h}, cur);
    case fc::kDiagnostics: return decode_diagnostics(h, cur);
    case fc::kWriteMultipleCoils: {
      WriteMultipleCoilsRequest pdu{h};
      pdu.addr = cur.u16();
      pdu.qty = cur.u16();
      pdu.byte_count = cur.u8();
      if (!cur.ok()) return truncated(h);
      pdu.coils = BitView(counted(pdu, cur.rest(), pdu.byte_count), pdu.qty);
      return pdu;
    }
    case fc::kWriteMultipleRegisters: {
      WriteMultipleRegistersRequest pdu{h};
      pdu.addr = cur.u16();
      pdu.qty = cur.u16();
      pdu.byte_count = cur.u8();
      if (!cur.ok()) return truncated(h);
      pdu.values = WordView(counted(pdu, cur.rest(), pdu.byte_count));
      return pdu;
    }
    case fc::kReadFileRecord:
      return decode_file_records(h, cur, FileRecordList::Layout::kReadRequest);
    case fc::kWriteFileRecord:
      return decode_file_records(h, cur, FileRecordList::Layout::kWriteRequest);
    case fc::kMaskWriteRegister: {
      MaskWrite pdu{h};
      pdu.addr = cur.u16();
      pdu.and_mask = cur.u16();
      pdu.or_mask = cur.u16();
      return finish_fixed(pdu, cur);
    }
    case fc::kReadWriteMultipleRegisters: {
      ReadWriteMultipleRequest pdu{h};
      pdu.read_addr = cur.u16();
      pdu.read_qty = cur.u16();
      pdu.write_addr = cur.u16();
      pdu.write_qty = cur.u16();
      pdu.byte_count = cur.u8();
      if (!cur.ok()) return truncated(h);
      pdu.values = WordView(counted(pdu, cur.rest(), pdu.byte_count));
      return pdu;
    }
    case fc::kReadFifoQueue: {
      FifoRequest pdu{h};
      pdu.addr = cur.u16();
      return finish_fixed(pdu, cur);
    }
    case fc::kEncapsulatedInterface: {
      const std::uint8_t mei = cur.u8();
      if (!cur.ok()) return truncated(h);
      if (mei == 0x0E) {
        DeviceIdRequest pdu{h};
        pdu.mei = mei;
        pdu.read_device_id_code = cur.u8();
        pdu.object_id = cur.u8();
        return finish_fixed(pdu, cur);
      }
      MeiPdu pdu{h};
      pdu.mei = mei;
      pdu.payload = cur.rest();
      return pdu;
    }
    default: return raw(h);
  }
}

DecodedPdu decode_exception(const PduHeader& h) {
  ByteCursor cur(h.data);
  ExceptionResponse pdu{h};
  pdu.code = cur.u8();
  return finish_fixed(pdu, cur);
}

DecodedPdu decode_response(const PduHeader& h, const Record& frame) {
  if ((h.function & fc::kExceptionBit) != 0) return decode_exception(h);
  ByteCursor cur(h.data);
  switch (h.function) {
    case fc::kReadCoils:
    case fc::kReadDiscreteInputs: {
      ReadBitsResponse pdu{h};
      pdu.byte_count = cur.u8();
      if (!cur.ok()) return truncated(h);
      const Bytes bits = counted(pdu, cur.rest(), pdu.byte_count);
      const ReadContext ctx = read_context(frame);
      pdu.addr = ctx.addr;
      pdu.qty = ctx.qty;
      pdu.bits = BitView(bits, ctx.qty ? *ctx.qty : bits.size() * 8);
      return pdu;
    }
    case fc::kReadHoldingRegisters:
    case fc::kReadInputRegisters:
    case fc::kReadWriteMultipleRegisters: {
      ReadRegistersResponse pdu{h};
      pdu.byte_count = cur.u8();
      if (!cur.ok()) return truncated(h);
      pdu.values = WordView(counted(pdu, cur.rest(), pdu.byte_count));
      const ReadContext ctx = read_context(frame);
      pdu.addr = ctx.addr;
      pdu.qty = ctx.qty;
      return pdu;
    }
    case fc::kWriteSingleCoil:
    case fc::kWriteSingleRegister: {
      WriteSingle pdu{h};
      pdu.addr = cur.u16();
      pdu.value = cur.u16();
      return finish_fixed(pdu, cur);
    }
    case fc::kReadExceptionStatus: {
      ExceptionStatusResponse pdu{h};
      pdu.status = cur.u8();
      return finish_fixed(pdu, cur);
    }
    case fc::kDiagnostics: return decode_diagnostics(h, cur);
    case fc::kGetCommEventCounter: {
      CommEventCounterResponse pdu{h};
      pdu.status = cur.u16();
      pdu.event_count = cur.u16();
      return finish_fixed(pdu, cur);
    }
    case fc::kGetCommEventLog: {
      CommEventLogResponse pdu{h};
      pdu.byte_count = cur.u8();
      if (!cur.ok()) return truncated(h);
      ByteCursor body(counted(pdu, cur.rest(), pdu.byte_count));
      pdu.status = body.u16();
      pdu.event_count = body.u16();
      pdu.message_count = body.u16();
      if (pdu.byte_count < 6) pdu.issues.add(IssueId::kByteCount);  // cannot hold the counters
      if (!body.ok()) {
        RawPdu out = truncated(h);
        out.issues.merge(pdu.issues);
        return out;
      }
      pdu.events = body.rest();
      return pdu;
    }
    case fc::kWriteMultipleCoils:
    case fc::kWriteMultipleRegisters: {
      WriteMultipleResponse pdu{h};
      pdu.addr = cur.u16();
      pdu.qty = cur.u16();
      return finish_fixed(pdu, cur);
    }
    case fc::kReportServerId: {
      ServerIdResponse pdu{h};
      pdu.byte_count = cur.u8();
      if (!cur.ok()) return truncated(h);
      pdu.payload = counted(pdu, cur.rest(), pdu.byte_count);
      return pdu;
    }
    case fc::kReadFileRecord:
      return decode_file_records(h, cur, FileRecordList::Layout::kReadResponse);
    case fc::kWriteFileRecord:  // an echo of the request
      return decode_file_records(h, cur, FileRecordList::Layout::kWriteRequest);
    case fc::kMaskWriteRegister: {
      MaskWrite pdu{h};
      pdu.addr = cur.u16();
      pdu.and_mask = cur.u16();
      pdu.or_mask = cur.u16();
      return finish_fixed(pdu, cur);
    }
    case fc::kReadFifoQueue: {
      // Byte count (2 bytes) covers the FIFO count and the values (§6.18).
      FifoResponse pdu{h};
      pdu.byte_count = cur.u16();
      if (!cur.ok()) return truncated(h);
      ByteCursor body(counted(pdu, cur.rest(), pdu.byte_count));
      pdu.fifo_count = body.u16();
      if (pdu.byte_count < 2) pdu.issues.add(IssueId::kByteCount);  // cannot hold the count
      if (!body.ok()) {
        RawPdu out = truncated(h);
        out.issues.merge(pdu.issues);
        return out;
      }
      pdu.values = WordView(body.rest());
      return pdu;
    }
    case fc::kEncapsulatedInterface: {
      const std::uint8_t mei = cur.u8();
      if (!cur.ok()) return truncated(h);
      if (mei == 0x0E) {
        DeviceIdResponse pdu{h};
        pdu.mei = mei;
        pdu.read_device_id_code = cur.u8();
        pdu.conformity = cur.u8();
        pdu.more_follows = cur.u8();
        pdu.next_object_id = cur.u8();
        pdu.object_count = cur.u8();
        if (!cur.ok()) return truncated(h);
        const Bytes body = cur.rest();
        pdu.objects = DeviceIdObjectList(body, pdu.object_count);
        if (!pdu.objects.complete()) {
          pdu.issues.add(IssueId::kTruncated);
        } else if (pdu.objects.used_bytes() < body.size()) {
          pdu.issues.add(IssueId::kExtraBytes);
        }
        return pdu;
      }
      MeiPdu pdu{h};
      pdu.mei = mei;
      pdu.payload = cur.rest();
      return pdu;
    }
    default: return raw(h);
  }
}

}  // namespace

const PduHeader& pdu_header(const DecodedPdu& pdu) {
  return std::visit([](const PduHeader& h) -> const PduHeader& { return h; }, pdu);
}

DecodedPdu decode_pdu(const Record& frame, Role role) {
  const PduHeader h = make_header(frame, role);
  if (frame.size < 2) return raw(h);  // not even a function code
  switch (role) {
    case Role::kRequest: return decode_request(h);
    case Role::kResponse: return decode_response(h, frame);
    case Role::kUnknown:
      if ((h.function & fc::kExceptionBit) != 0) return decode_exception(h);
      return raw(h);
  }
  return raw(h);
}

}  // namespace rtu
