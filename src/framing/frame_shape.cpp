#include "framing/frame_shape.hpp"

#include "core/function_codes.hpp"

namespace rtu {
namespace {

// Length = fixed part + the byte count found at `offset` (MODBUS App. Protocol V1.1b3 §6).
Shape with_byte_count(std::span<const std::uint8_t> p, std::size_t offset, std::size_t fixed) {
  if (p.size() <= offset) return Shape::need(offset + 1);
  return Shape::length(fixed + p[offset]);
}

// FC43 / MEI 0x0E response has no total length: walk the objects (§6.21).
Shape device_id_response(std::span<const std::uint8_t> p) {
  constexpr std::size_t kHeader = 8;  // addr fc mei code conformity more next count
  if (p.size() < kHeader) return Shape::need(kHeader);
  std::size_t pos = kHeader;
  const unsigned objects = p[7];
  for (unsigned i = 0; i < objects; ++i) {
    if (p.size() < pos + 2) return Shape::need(pos + 2);
    pos += 2U + p[pos + 1];
    if (pos + 2 > kMaxAdu) return Shape::impossible();
  }
  return Shape::length(pos + 2);
}

Shape request_shape(std::span<const std::uint8_t> p, std::uint8_t function) {
  switch (function) {
    case fc::kReadCoils:
    case fc::kReadDiscreteInputs:
    case fc::kReadHoldingRegisters:
    case fc::kReadInputRegisters:
    case fc::kWriteSingleCoil:
    case fc::kWriteSingleRegister: return Shape::length(8);
    case fc::kReadExceptionStatus:
    case fc::kGetCommEventCounter:
    case fc::kGetCommEventLog:
    case fc::kReportServerId: return Shape::length(4);
    case fc::kDiagnostics:
      // Sub-function 0 (Return Query Data) echoes any amount of data.
      if (p.size() < 4) return Shape::need(4);
      if (p[2] == 0 && p[3] == 0) return Shape::unpredictable();
      return Shape::length(8);
    case fc::kWriteMultipleCoils:
    case fc::kWriteMultipleRegisters: return with_byte_count(p, 6, 9);
    case fc::kReadFileRecord:
    case fc::kWriteFileRecord: return with_byte_count(p, 2, 5);
    case fc::kMaskWriteRegister: return Shape::length(10);
    case fc::kReadWriteMultipleRegisters: return with_byte_count(p, 10, 13);
    case fc::kReadFifoQueue: return Shape::length(6);
    case fc::kEncapsulatedInterface:
      if (p.size() < 3) return Shape::need(3);
      return p[2] == 0x0E ? Shape::length(7) : Shape::unpredictable();
    default: return Shape::unpredictable();
  }
}

Shape response_shape(std::span<const std::uint8_t> p, std::uint8_t function) {
  if ((function & fc::kExceptionBit) != 0) return Shape::length(5);
  switch (function) {
    case fc::kReadHoldingRegisters:
    case fc::kReadInputRegisters:
    case fc::kReadWriteMultipleRegisters:
      // Register data: the byte count is 2 × quantity, so never odd (V1.1b3 §6.3).
      if (p.size() > 2 && (p[2] % 2 != 0 || p[2] == 0)) return Shape::impossible();
      return with_byte_count(p, 2, 5);
    case fc::kReadCoils:
    case fc::kReadDiscreteInputs:
    case fc::kGetCommEventLog:
    case fc::kReportServerId:
    case fc::kReadFileRecord:
    case fc::kWriteFileRecord: return with_byte_count(p, 2, 5);
    case fc::kWriteSingleCoil:
    case fc::kWriteSingleRegister:
    case fc::kGetCommEventCounter:
    case fc::kWriteMultipleCoils:
    case fc::kWriteMultipleRegisters: return Shape::length(8);
    case fc::kReadExceptionStatus: return Shape::length(5);
    case fc::kDiagnostics:
      return request_shape(p, function);  // an echo, or a 2-byte counter: same length
    case fc::kMaskWriteRegister: return Shape::length(10);
    case fc::kReadFifoQueue: {
      if (p.size() < 4) return Shape::need(4);
      const std::size_t count = (std::size_t{p[2]} << 8U) | p[3];
      return Shape::length(6 + count);
    }
    case fc::kEncapsulatedInterface:
      if (p.size() < 3) return Shape::need(3);
      return p[2] == 0x0E ? device_id_response(p) : Shape::unpredictable();
    default: return Shape::unpredictable();
  }
}

}  // namespace

Shape predict_shape(std::span<const std::uint8_t> prefix, Role role) {
  if (prefix.size() < 2) return Shape::need(2);
  const std::uint8_t function = prefix[1];
  if (function == 0) return Shape::impossible();  // 0 is never a valid function code
  if (role == Role::kRequest) {
    if ((function & fc::kExceptionBit) != 0) return Shape::impossible();
    return request_shape(prefix, function);
  }
  if (role == Role::kResponse) {
    if (prefix[0] == 0) return Shape::impossible();  // broadcasts are never answered
    return response_shape(prefix, function);
  }
  return Shape::unpredictable();
}

}  // namespace rtu
