#pragma once
// What a request (and its normal response) reads from or writes to a slave's four data
// tables (MODBUS Application Protocol V1.1b3 §4.3): the one place that turns the data
// functions (FC01-06, 15, 16, 22, 23) into address ranges and values, so every user agrees
// on them, FC23 included. Built on decode_pdu(); allocation-free: the views point into the
// Records, which must outlive the DataAccess.
//
// Policy stays with the callers: a block says what the bytes hold and whether its byte count
// fits; whether to trust values whose count does not fit is theirs to decide.
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "core/issue.hpp"
#include "framing/record.hpp"
#include "modbus/pdu_views.hpp"

namespace rtu {

enum class DataTable : std::uint8_t { kCoils, kDiscreteInputs, kHoldingRegisters, kInputRegisters };

// "coil", "discrete", "holding", "input": the names raw points are given.
std::string_view data_table_name(DataTable table);

// Coils and discrete inputs count bits; the register tables count 16-bit words.
constexpr bool is_bit_table(DataTable table) {
  return table == DataTable::kCoils || table == DataTable::kDiscreteInputs;
}

// The table a function code addresses: 1, 5, 15 coils; 2 discrete inputs; 3, 6, 16, 22, 23
// holding registers; 4 input registers. Nothing for the other functions.
std::optional<DataTable> data_table_of(std::uint8_t function);

// One contiguous range of one table.
struct DataBlock {
  DataTable table = DataTable::kHoldingRegisters;
  std::uint16_t addr = 0;
  std::uint16_t qty = 0;  // registers or bits, as the table counts
  bool write = false;     // the data goes to the device
  // The values are known: for a read, from the normal response; for a write, from the
  // request (FC22 never: the result depends on what the register held).
  bool has_values = false;
  // The byte count equals what the quantity needs and the frame holds exactly that many
  // bytes. True for the fixed layouts (FC05, 06, 22).
  bool count_fits = false;
  bool invalid_value = false;  // FC05 value neither FF00 nor 0000: has_values is false
  // Values in the block's order, never more than qty and never past the bytes present:
  // `words` for the register tables, `bits` for the bit tables (the other one is empty).
  WordView words{};
  BitView bits{};
};

// At most two blocks: FC23 writes one range and reads another.
struct DataAccess {
  std::array<DataBlock, 2> blocks{};
  std::uint8_t count = 0;
  // Structural problems decode_pdu() found in the request and, when one of the same function
  // was given, the response (kTruncated, kByteCount, kExtraBytes).
  IssueSet issues;

  [[nodiscard]] const DataBlock* begin() const { return blocks.data(); }
  [[nodiscard]] const DataBlock* end() const { return blocks.data() + count; }
  [[nodiscard]] bool empty() const { return count == 0; }
  // The block read from the device, or written to it; null when there is none.
  [[nodiscard]] const DataBlock* read() const;
  [[nodiscard]] const DataBlock* write() const;
};

// What `request` accesses; values of a read come from `response` when it is a response of
// the same function (an exception, or null, leaves them unknown). Blocks are in the order
// the device performs them: FC23 writes before it reads. A request that is not a data
// function, or too short for its fixed fields, accesses nothing.
// Each record's decoding is the tracker's (Record::pdu) where it made one.
DataAccess data_access(const Record& request, const Record* response);

}  // namespace rtu
