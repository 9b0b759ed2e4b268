#pragma once
// The values of a slave that has no device map: raw 16-bit registers and single bits at
// their protocol addresses, named "holding 0x0032", "input 0x0032", "coil 0x0010",
// "discrete 0x0010", as data_access() reads them. Read values come from normal responses to
// FC01-04 and FC23; written values from requests that a normal response confirms (FC05, 06,
// 15, 16, 23). Only frames that carry_values() and whose byte counts fit their quantities
// exactly give values: a value is reported only when the bytes are trustworthy.
#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <vector>

#include "core/flat_index.hpp"
#include "dissect/point_value.hpp"
#include "framing/record.hpp"
#include "modbus/data_access.hpp"

namespace rtu::dissect {

// Whether `frame` is a response whose data can be trusted as values: a normal response with
// a good CRC to a request of the same slave and function with a good CRC, neither with a
// byte count that contradicts its frame.
bool carries_values(const Record& frame);

class RawValues {
 public:
  // Appends the values `response` carries to `out`. Their names live in this object until
  // the next call.
  void collect(const Record& response, std::vector<PointValue>& out);

 private:
  // The name of a table's address, formatted once: a bus polls the same registers again
  // and again. Bounded: past kMaxNames the names are made anew.
  std::string_view name_of(std::uint64_t key, DataTable table, std::uint32_t addr);
  static constexpr std::size_t kMaxNames = 16384;
  std::deque<std::string> name_texts_;  // a deque: its strings never move as it grows
  FlatIndex<std::string_view> names_;   // key → its text in name_texts_
};

}  // namespace rtu::dissect
