#include "dissect/raw_values.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <string_view>

#include "modbus/data_access.hpp"

namespace rtu::dissect {

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
  // Only blocks whose byte counts fit exactly, from frames with nothing missing or extra.
  const DataAccess access = data_access(*frame.request, &frame);
  if (!access.issues.empty()) return;
  const std::size_t first = out.size();
  auto add = [&](std::string_view table, std::uint32_t addr, double value) {
    const std::size_t i = out.size() - first;
    if (i == names_.size()) names_.emplace_back();
    names_[i].assign(table);
    fmt::format_to(std::back_inserter(names_[i]), " 0x{:04X}", addr);
    PointValue v;
    v.t = frame.t_start;
    v.slave = frame.slave();
    v.value = value;
    out.push_back(v);
  };
  // In the device's order: FC23's read shows the registers after its write.
  for (const DataBlock& b : access) {
    if (!b.has_values || !b.count_fits) continue;
    const std::string_view table = data_table_name(b.table);
    for (std::size_t k = 0; k < b.words.size(); ++k)
      add(table, b.addr + static_cast<std::uint32_t>(k), b.words[k]);
    for (std::size_t k = 0; k < b.bits.size(); ++k)
      add(table, b.addr + static_cast<std::uint32_t>(k), b.bits[k] ? 1 : 0);
  }
  // Named once all are in: growing names_ above may move the strings.
  for (std::size_t i = first; i < out.size(); ++i) out[i].point = names_[i - first];
}

}  // namespace rtu::dissect
