#include "dissect/raw_values.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <string_view>

#include "core/function_codes.hpp"

namespace rtu::dissect {

namespace {

std::uint16_t word_at(std::span<const std::uint8_t> b, std::size_t i) {
  return static_cast<std::uint16_t>((b[i] << 8U) | b[i + 1]);
}

// Bit k of the packed bits starting at byte `first` (LSB of the first byte is bit 0).
double bit_at(std::span<const std::uint8_t> b, std::size_t first, std::uint32_t k) {
  return static_cast<double>((static_cast<unsigned>(b[first + k / 8U]) >> (k % 8U)) & 1U);
}

// Hands every value `frame` (a response that carries_values) holds to `emit(space, address,
// value)`.
template <typename Emit>
void for_each_raw_value(const Record& frame, const Emit& emit) {
  const auto rsp = frame.bytes();
  const auto req = frame.request->bytes();
  const std::uint8_t fc = frame.function();
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

}  // namespace

bool carries_values(const Record& frame) {
  if (frame.kind != RecordKind::kFrame || frame.size < 4 || !frame.crc_ok ||
      frame.role != Role::kResponse || frame.request == nullptr || frame.is_exception() ||
      !frame.request->crc_ok) {
    return false;
  }
  const Record& request = *frame.request;
  if (request.slave() != frame.slave() || request.function() != frame.function()) return false;
  return !frame.issues.has(IssueId::kByteCount) && !request.issues.has(IssueId::kByteCount);
}

void RawValues::collect(const Record& frame, std::vector<PointValue>& out) {
  if (!carries_values(frame)) return;
  const std::size_t first = out.size();
  for_each_raw_value(frame, [&](std::string_view space, std::uint32_t addr, double value) {
    const std::size_t i = out.size() - first;
    if (i == names_.size()) names_.emplace_back();
    names_[i].assign(space);
    fmt::format_to(std::back_inserter(names_[i]), " 0x{:04X}", addr);
    PointValue v;
    v.t = frame.t_start;
    v.slave = frame.slave();
    v.value = value;
    out.push_back(v);
  });
  // Named once all are in: growing names_ above may move the strings.
  for (std::size_t i = first; i < out.size(); ++i) out[i].point = names_[i - first];
}

}  // namespace rtu::dissect
