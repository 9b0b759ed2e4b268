#pragma once
// Turns a frame of a known device into named, scaled points, using the device's map and
// what has been learned so far about that slave (e.g. its PT and CT ratios).
//
// Reads are decoded on the response (the request, via Record::request, gives the start
// address and quantity); writes are decoded on the request (what is written, where) and
// learned from when the normal response confirms them. Device-level findings are issues on
// the frame: out_of_range, undefined_register, read_only_write, scale_unknown,
// reserved_nonzero, partial_point, unsupported_function, and bytecount for a write whose
// byte count contradicts its quantity (decoded as far as its bytes go).
#include <cstdint>
#include <optional>
#include <vector>

#include "core/issue.hpp"
#include "dissect/device_map.hpp"
#include "dissect/read_range_checks.hpp"
#include "dissect/register_plans.hpp"
#include "framing/record.hpp"
#include "modbus/data_access.hpp"

namespace rtu::dissect {

// What has been learned about one slave: one entry per DeviceMap::vars.
struct SlaveState {
  std::vector<std::optional<double>> vars;
  void reset(const DeviceMap& map) { vars.assign(map.vars.size(), std::nullopt); }
};

struct DecodedPoint {
  const Point* point = nullptr;  // null: an address the map does not define
  std::uint32_t addr = 0;        // in the space's addressing
  std::uint8_t spare_index = 0;  // > 0: the n-th spare register after `point`
  std::uint8_t raw_bytes = 0;    // bytes behind `raw` (1, 2 or 4); 0 for a bit point
  bool partial = false;          // only part of a multi-register point was transferred
  std::uint64_t raw = 0;         // as on the wire, word order applied (unsigned bits)
  bool has_value = false;
  double base = 0.0;               // raw × scale + offset (what `range` constrains)
  double value = 0.0;              // base × every scale_by var (valid when has_value)
  std::uint32_t assumed_vars = 0;  // bit i: var i unknown, its default used
  std::uint32_t unknown_vars = 0;  // bit i: var i unknown, no default: no value
};

struct Decoded {
  const DeviceMap* map = nullptr;
  const Space* space = nullptr;
  std::vector<DecodedPoint> points;  // in address order
  // On the normal response to a write: the values that write set, now confirmed (decoded
  // from the request, scaled with what the write itself taught). Empty otherwise.
  std::vector<DecodedPoint> confirmed;
  IssueSet issues;
  void clear() {
    map = nullptr;
    space = nullptr;
    points.clear();
    confirmed.clear();
    issues = IssueSet{};
  }
};

class RegisterDecoder {
 public:
  // Decodes `frame` (its role and, for a response, `frame.request` set by pairing) into
  // `out` (cleared first) and updates `state`. Frames it cannot relate to the map (unknown
  // role, exception responses, CRC failures) leave `out` empty.
  void decode(const DeviceMap& map, SlaveState& state, const Record& frame, Decoded& out) {
    decode(map, state, frame, nullptr, out);
  }
  // The same, for a caller that already knows what a request frame accesses
  // (data_access(frame, nullptr)); null: it is found here. Unused for other frames.
  void decode(const DeviceMap& map, SlaveState& state, const Record& frame,
              const DataAccess* request_access, Decoded& out);

 private:
  Decoded scratch_;  // confirmed writes are decoded here to learn from them
  ReadRangeChecks read_checks_;
  RegisterPlans plans_;
};

// The enum text of a point's value, or null when the value is not listed.
const EnumEntry* find_enum(const Point& point, std::int64_t value);
// The raw value as a signed or unsigned integer per the point's type.
std::int64_t raw_as_integer(const Point& point, std::uint64_t raw);

}  // namespace rtu::dissect
