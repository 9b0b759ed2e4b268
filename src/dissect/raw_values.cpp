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

std::string_view RawValues::name_of(std::uint64_t key, DataTable table, std::uint32_t addr) {
  if (const std::string_view* known = names_.find(key)) return *known;
  // Names handed out earlier in this call stay valid: a deque's elements never move, and
  // the names are only forgotten before a record's first value.
  const std::string_view name =
      name_texts_.emplace_back(fmt::format("{} 0x{:04X}", data_table_name(table), addr));
  names_.put(key, name);
  return name;
}

void RawValues::collect(const Record& frame, std::vector<PointValue>& out) {
  if (!carries_values(frame)) return;
  // Only blocks whose byte counts fit exactly, from frames with nothing missing or extra.
  const DataAccess access = data_access(*frame.request, &frame);
  if (!access.issues.empty()) return;
  if (names_.size() > kMaxNames) {
    names_.clear();
    name_texts_.clear();
  }
  const std::uint8_t slave = frame.slave();
  auto add = [&](DataTable table, std::uint32_t addr, double value) {
    // Filled in place, as the device stage fills a map's values (a PointValue built on the
    // stack and copied in stalls on the copy), and its table named only for a new name.
    PointValue& v = out.emplace_back();
    v.t = frame.t_start;
    v.slave = slave;
    v.key = raw_point_key(static_cast<unsigned>(table), addr);
    v.point = name_of(v.key, table, addr);
    v.value = value;
  };
  // In the device's order: FC23's read shows the registers after its write.
  for (const DataBlock& b : access) {
    if (!b.has_values || !b.count_fits) continue;
    for (std::size_t k = 0; k < b.words.size(); ++k)
      add(b.table, b.addr + static_cast<std::uint32_t>(k), b.words[k]);
    for (std::size_t k = 0; k < b.bits.size(); ++k)
      add(b.table, b.addr + static_cast<std::uint32_t>(k), b.bits[k] ? 1 : 0);
  }
}

}  // namespace rtu::dissect
