#include "timeline.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace rtu::sim {

TruthRecord frame_record(Bytes bytes, TruthRole role, std::uint64_t txn, std::string_view device) {
  TruthRecord r;
  r.kind = TruthKind::kFrame;
  r.bytes = std::move(bytes);
  r.role = role;
  r.txn = txn;
  r.device = device;
  return r;
}

TruthRecord noise_record(Bytes bytes, std::string_view cause) {
  TruthRecord r;
  r.kind = TruthKind::kNoise;
  r.bytes = std::move(bytes);
  r.cause = cause;
  return r;
}

void Timeline::check_start(Nanos start) const {
  if (start < wire_end()) {
    throw std::logic_error(
        fmt::format("simulator bug: record starts at {} ns, before the wire is "
                    "free at {} ns",
                    start, wire_end()));
  }
}

void Timeline::add_fault(TruthRecord& record, std::string_view fault) {
  for (const auto f : record.faults) {
    if (f == fault) return;
  }
  record.faults.push_back(fault);
}

}  // namespace rtu::sim
