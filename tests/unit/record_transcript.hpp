#pragma once
// A record as one line of text with every field the framing and the tracker gave it, for
// tests that compare two decodings record by record.
#include <fmt/format.h>

#include <string>

#include "framing/record.hpp"

namespace rtu::testing {

inline std::string describe_record(const Record& r) {
  return fmt::format(
      "record kind={} seq={} t={}..{} gap={} origin={} errors={} fit={} crc={} issues={:x} "
      "role={} txn={} latency={} request={} {:02x}",
      static_cast<int>(r.kind), r.seq, r.t_start, r.t_end, r.gap_before, r.origin, r.line_errors,
      r.shape_fit, r.crc_ok, r.issues.bits(), static_cast<int>(r.role), r.txn, r.latency,
      r.request != nullptr ? r.request->seq : -1ULL, fmt::join(r.bytes(), ""));
}

}  // namespace rtu::testing
