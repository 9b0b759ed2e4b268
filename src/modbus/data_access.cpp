// data_access(): the data functions' ranges and values, read off decode_pdu()'s structs.
#include "modbus/data_access.hpp"

#include <algorithm>
#include <span>
#include <variant>

#include "core/function_codes.hpp"
#include "modbus/pdu.hpp"

namespace rtu {
namespace {

using Bytes = std::span<const std::uint8_t>;

std::size_t bit_bytes(std::uint16_t qty) {
  return (std::size_t{qty} + 7U) / 8U;
}

// The first `qty` registers of the bytes a byte count covers; an odd byte is no register.
WordView words_for(Bytes counted, std::uint16_t qty) {
  const std::size_t n = std::min(counted.size(), 2U * std::size_t{qty});
  return WordView(counted.first(n - n % 2U));
}

// The first `qty` bits of the bytes a byte count covers.
BitView bits_for(Bytes counted, std::uint16_t qty) {
  return BitView(counted.first(std::min(counted.size(), bit_bytes(qty))), qty);
}

// decode_pdu() flags kByteCount when the bytes present differ from the byte count; the
// count must also be what the quantity needs.
bool fits(const PduHeader& pdu, std::size_t byte_count, std::size_t needed) {
  return byte_count == needed && !pdu.issues.has(IssueId::kByteCount);
}

DataBlock block(std::uint8_t function, std::uint16_t addr, std::uint16_t qty, bool write) {
  DataBlock b;
  b.table = data_table_of(function).value_or(DataTable::kHoldingRegisters);
  b.addr = addr;
  b.qty = qty;
  b.write = write;
  return b;
}

// The registers a write request (FC16, FC23's write part) puts on the device.
DataBlock registers_written(const PduHeader& r, std::uint16_t addr, std::uint16_t qty,
                            std::uint8_t byte_count, WordView values) {
  DataBlock b = block(r.function, addr, qty, true);
  b.has_values = true;
  b.count_fits = fits(r, byte_count, 2U * std::size_t{qty});
  b.words = words_for(values.bytes(), qty);
  return b;
}

class Builder {
 public:
  explicit Builder(DataAccess& out) : out_(out) {}

  void operator()(const ReadRequest& r) { add(block(r.function, r.addr, r.qty, false)); }

  void operator()(const WriteSingle& r) {
    DataBlock b = block(r.function, r.addr, 1, true);
    b.count_fits = true;
    // The value's bytes follow the address in the PDU data.
    const Bytes value = r.data.subspan(2, 2);
    if (r.function == fc::kWriteSingleCoil) {
      // FF00 / 0000: the high byte alone, read as a bit, is the coil's state.
      b.invalid_value = !r.coil().has_value();
      b.has_values = !b.invalid_value;
      if (b.has_values) b.bits = BitView(value.first(1), 1);
    } else {
      b.has_values = true;
      b.words = WordView(value);
    }
    add(b);
  }

  void operator()(const WriteMultipleCoilsRequest& r) {
    DataBlock b = block(r.function, r.addr, r.qty, true);
    b.has_values = true;
    b.count_fits = fits(r, r.byte_count, bit_bytes(r.qty));
    b.bits = bits_for(r.coils.bytes(), r.qty);
    add(b);
  }

  void operator()(const WriteMultipleRegistersRequest& r) {
    add(registers_written(r, r.addr, r.qty, r.byte_count, r.values));
  }

  void operator()(const MaskWrite& r) {
    DataBlock b = block(r.function, r.addr, 1, true);
    b.count_fits = true;
    add(b);
  }

  void operator()(const ReadWriteMultipleRequest& r) {
    // The device writes first, then reads (V1.1b3 §6.17): blocks in that order.
    add(registers_written(r, r.write_addr, r.write_qty, r.byte_count, r.values));
    add(block(r.function, r.read_addr, r.read_qty, false));
  }

  // Every other PDU accesses no data table.
  template <typename T>
  void operator()(const T& /*pdu*/) {}

 private:
  void add(const DataBlock& b) { out_.blocks.at(out_.count++) = b; }
  DataAccess& out_;
};

// Puts a normal response's values into the read block.
void fill_read(DataBlock& b, const DecodedPdu& response) {
  if (const auto* regs = std::get_if<ReadRegistersResponse>(&response)) {
    b.has_values = true;
    b.count_fits = fits(*regs, regs->byte_count, 2U * std::size_t{b.qty});
    b.words = words_for(regs->values.bytes(), b.qty);
  } else if (const auto* bits = std::get_if<ReadBitsResponse>(&response)) {
    b.has_values = true;
    b.count_fits = fits(*bits, bits->byte_count, bit_bytes(b.qty));
    b.bits = bits_for(bits->bits.bytes(), b.qty);
  }
}

}  // namespace

std::string_view data_table_name(DataTable table) {
  switch (table) {
    case DataTable::kCoils: return "coil";
    case DataTable::kDiscreteInputs: return "discrete";
    case DataTable::kHoldingRegisters: return "holding";
    case DataTable::kInputRegisters: return "input";
  }
  return "?";
}

std::optional<DataTable> data_table_of(std::uint8_t function) {
  switch (function) {
    case fc::kReadCoils:
    case fc::kWriteSingleCoil:
    case fc::kWriteMultipleCoils: return DataTable::kCoils;
    case fc::kReadDiscreteInputs: return DataTable::kDiscreteInputs;
    case fc::kReadHoldingRegisters:
    case fc::kWriteSingleRegister:
    case fc::kWriteMultipleRegisters:
    case fc::kMaskWriteRegister:
    case fc::kReadWriteMultipleRegisters: return DataTable::kHoldingRegisters;
    case fc::kReadInputRegisters: return DataTable::kInputRegisters;
    default: return std::nullopt;
  }
}

const DataBlock* DataAccess::read() const {
  for (const DataBlock& b : *this) {
    if (!b.write) return &b;
  }
  return nullptr;
}

const DataBlock* DataAccess::write() const {
  for (const DataBlock& b : *this) {
    if (b.write) return &b;
  }
  return nullptr;
}

namespace {

// The request's blocks, from its decoding.
DataAccess request_access(const DecodedPdu& req) {
  DataAccess out;
  out.issues = pdu_header(req).issues;
  std::visit(Builder(out), req);
  return out;
}

bool response_counts(const DataAccess& out, const Record& request, const Record* response) {
  return !out.empty() && response != nullptr && response->function() == request.function();
}

// The read's values, from the response's decoding.
void add_response(DataAccess& out, const DecodedPdu& rsp) {
  out.issues.merge(pdu_header(rsp).issues);
  for (DataBlock& b : std::span(out.blocks.data(), out.count)) {
    if (!b.write) fill_read(b, rsp);
  }
}

}  // namespace

DataAccess data_access(const Record& request, const Record* response) {
  // Not decoding_of(): its scratch costs this, asked several times a frame, 1% of the
  // pairing thread.
  const DecodedPdu* req = tracker_decoding(request, Role::kRequest);
  DataAccess out =
      req != nullptr ? request_access(*req) : request_access(decode_pdu(request, Role::kRequest));
  if (response_counts(out, request, response)) {
    if (const DecodedPdu* rsp = tracker_decoding(*response, Role::kResponse)) {
      add_response(out, *rsp);
    } else {
      add_response(out, decode_pdu(*response, Role::kResponse));
    }
  }
  return out;
}

}  // namespace rtu
