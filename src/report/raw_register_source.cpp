#include "report/raw_register_source.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <string_view>

#include "core/function_codes.hpp"

namespace rtu {

namespace {

std::uint16_t word_at(std::span<const std::uint8_t> b, std::size_t i) {
  return static_cast<std::uint16_t>((b[i] << 8U) | b[i + 1]);
}

// Bit k of the packed bits starting at byte `first` (LSB of the first byte is bit 0).
double bit_at(std::span<const std::uint8_t> b, std::size_t first, std::uint32_t k) {
  return static_cast<double>((static_cast<unsigned>(b[first + k / 8U]) >> (k % 8U)) & 1U);
}

}  // namespace

void RawRegisterSource::extract(const Record& frame, PointSink& sink) {
  if (frame.kind != RecordKind::kFrame || !frame.crc_ok || frame.role != Role::kResponse ||
      frame.request == nullptr || frame.is_exception() || !frame.request->crc_ok) {
    return;
  }
  const Record& request = *frame.request;
  if (request.slave() != frame.slave() || request.function() != frame.function()) return;
  if (frame.issues.has(IssueId::kByteCount) || request.issues.has(IssueId::kByteCount)) return;
  const auto rsp = frame.bytes();
  const auto req = request.bytes();
  const std::uint8_t fc = frame.function();

  auto emit = [&](std::string_view space, std::uint32_t addr, double value) {
    const auto end = fmt::format_to_n(name_.data(), name_.size() - 1, "{} 0x{:04X}", space, addr);
    PointSample s;
    s.t = frame.t_start;
    s.slave = frame.slave();
    s.point = std::string_view(name_.data(), end.size < name_.size() ? end.size : 0);
    s.value = value;
    sink.on_point(s);
  };

  switch (fc) {
    case fc::kReadHoldingRegisters:
    case fc::kReadInputRegisters: {
      if (req.size() != 8 || rsp.size() < 5) return;
      const std::uint16_t addr = word_at(req, 2);
      const std::uint16_t qty = word_at(req, 4);
      const std::size_t byte_count = rsp[2];
      if (byte_count != 2U * qty || rsp.size() != byte_count + 5U) return;
      const std::string_view space = fc == fc::kReadHoldingRegisters ? "holding" : "input";
      for (std::uint32_t k = 0; k < qty; ++k)
        emit(space, addr + k, word_at(rsp, 3 + 2 * std::size_t{k}));
      return;
    }
    case fc::kReadCoils:
    case fc::kReadDiscreteInputs: {
      if (req.size() != 8 || rsp.size() < 5) return;
      const std::uint16_t addr = word_at(req, 2);
      const std::uint16_t qty = word_at(req, 4);
      const std::size_t byte_count = rsp[2];
      if (byte_count != (qty + 7U) / 8U || rsp.size() != byte_count + 5U) return;
      const std::string_view space = fc == fc::kReadCoils ? "coil" : "discrete";
      for (std::uint32_t k = 0; k < qty; ++k) {
        emit(space, addr + k, bit_at(rsp, 3, k));
      }
      return;
    }
    case fc::kWriteSingleCoil:
      if (rsp.size() != 8) return;
      if (word_at(rsp, 4) == 0xFF00) emit("coil", word_at(rsp, 2), 1);
      if (word_at(rsp, 4) == 0x0000) emit("coil", word_at(rsp, 2), 0);
      return;
    case fc::kWriteSingleRegister:
      if (rsp.size() != 8) return;
      emit("holding", word_at(rsp, 2), word_at(rsp, 4));
      return;
    case fc::kWriteMultipleRegisters: {
      if (req.size() < 9) return;
      const std::uint16_t addr = word_at(req, 2);
      const std::uint16_t qty = word_at(req, 4);
      if (req[6] != 2U * qty || req.size() != 9U + req[6]) return;
      for (std::uint32_t k = 0; k < qty; ++k)
        emit("holding", addr + k, word_at(req, 7 + 2 * std::size_t{k}));
      return;
    }
    case fc::kWriteMultipleCoils: {
      if (req.size() < 9) return;
      const std::uint16_t addr = word_at(req, 2);
      const std::uint16_t qty = word_at(req, 4);
      if (req[6] != (qty + 7U) / 8U || req.size() != 9U + req[6]) return;
      for (std::uint32_t k = 0; k < qty; ++k) emit("coil", addr + k, bit_at(req, 7, k));
      return;
    }
    default: return;
  }
}

}  // namespace rtu
