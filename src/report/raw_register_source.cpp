#include "report/raw_register_source.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <string_view>

#include "modbus/data_access.hpp"

namespace rtu {

void RawRegisterSource::extract(const Record& frame, PointSink& sink) {
  if (frame.kind != RecordKind::kFrame || !frame.crc_ok || frame.role != Role::kResponse ||
      frame.request == nullptr || frame.is_exception() || !frame.request->crc_ok) {
    return;
  }
  const Record& request = *frame.request;
  if (request.slave() != frame.slave() || request.function() != frame.function()) return;
  if (frame.issues.has(IssueId::kByteCount) || request.issues.has(IssueId::kByteCount)) return;
  // Only blocks whose byte counts fit exactly, from frames with nothing missing or extra.
  const DataAccess access = data_access(request, &frame);
  if (!access.issues.empty()) return;

  auto emit = [&](std::string_view space, std::uint32_t addr, double value) {
    const auto end = fmt::format_to_n(name_.data(), name_.size() - 1, "{} 0x{:04X}", space, addr);
    PointSample s;
    s.t = frame.t_start;
    s.slave = frame.slave();
    s.point = std::string_view(name_.data(), end.size < name_.size() ? end.size : 0);
    s.value = value;
    sink.on_point(s);
  };

  // In the device's order: FC23's read shows the registers after its write.
  for (const DataBlock& b : access) {
    if (!b.has_values || !b.count_fits) continue;
    const std::string_view space = data_table_name(b.table);
    for (std::size_t k = 0; k < b.words.size(); ++k)
      emit(space, b.addr + static_cast<std::uint32_t>(k), b.words[k]);
    for (std::size_t k = 0; k < b.bits.size(); ++k)
      emit(space, b.addr + static_cast<std::uint32_t>(k), b.bits[k] ? 1 : 0);
  }
}

}  // namespace rtu
