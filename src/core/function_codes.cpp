#include "core/function_codes.hpp"

#include <algorithm>
#include <iterator>

namespace rtu {
namespace {

struct FunctionNames {
  std::uint8_t code;
  std::string_view name;
  std::string_view short_name;
};

constexpr FunctionNames kFunctions[] = {
    {fc::kReadCoils, "Read Coils", "read coils"},
    {fc::kReadDiscreteInputs, "Read Discrete Inputs", "read inputs"},
    {fc::kReadHoldingRegisters, "Read Holding Registers", "read holding"},
    {fc::kReadInputRegisters, "Read Input Registers", "read input regs"},
    {fc::kWriteSingleCoil, "Write Single Coil", "write coil"},
    {fc::kWriteSingleRegister, "Write Single Register", "write register"},
    {fc::kReadExceptionStatus, "Read Exception Status", "read exc status"},
    {fc::kDiagnostics, "Diagnostics", "diagnostics"},
    {fc::kGetCommEventCounter, "Get Comm Event Counter", "event counter"},
    {fc::kGetCommEventLog, "Get Comm Event Log", "event log"},
    {fc::kWriteMultipleCoils, "Write Multiple Coils", "write coils"},
    {fc::kWriteMultipleRegisters, "Write Multiple Registers", "write registers"},
    {fc::kReportServerId, "Report Server ID", "report server id"},
    {fc::kReadFileRecord, "Read File Record", "read file"},
    {fc::kWriteFileRecord, "Write File Record", "write file"},
    {fc::kMaskWriteRegister, "Mask Write Register", "mask write"},
    {fc::kReadWriteMultipleRegisters, "Read/Write Multiple Registers", "read/write regs"},
    {fc::kReadFifoQueue, "Read FIFO Queue", "read fifo"},
    {fc::kEncapsulatedInterface, "Encapsulated Interface Transport", "mei"},
};

const FunctionNames* find_function(std::uint8_t function) {
  for (const auto& f : kFunctions) {
    if (f.code == function) return &f;
  }
  return nullptr;
}

// One bit per public code (all are below 64): the framer and the PDU check ask this of
// every frame, where the search through the names took about 40 instructions.
constexpr std::uint64_t public_function_bits() {
  std::uint64_t bits = 0;
  for (const auto& f : kFunctions) bits |= std::uint64_t{1} << f.code;
  return bits;
}
constexpr std::uint64_t kPublicFunctionBits = public_function_bits();
static_assert(std::all_of(std::begin(kFunctions), std::end(kFunctions),
                          [](const FunctionNames& f) { return f.code < 64; }),
              "every public code has its bit");

}  // namespace

bool is_public_function(std::uint8_t function) {
  return function < 64 && ((kPublicFunctionBits >> function) & 1U) != 0;
}

bool is_user_defined_function(std::uint8_t function) {
  return (function >= 65 && function <= 72) || (function >= 100 && function <= 110);
}

bool may_be_broadcast(std::uint8_t function) {
  switch (function) {
    case fc::kWriteSingleCoil:
    case fc::kWriteSingleRegister:
    case fc::kWriteMultipleCoils:
    case fc::kWriteMultipleRegisters:
    case fc::kWriteFileRecord:
    case fc::kMaskWriteRegister:
    case fc::kDiagnostics: return true;
    default: return !is_public_function(function);
  }
}

std::string_view function_name(std::uint8_t function) {
  const auto* f = find_function(function & 0x7FU);
  if (f != nullptr) return f->name;
  if (is_user_defined_function(function & 0x7FU)) return "User-defined function";
  return "Unknown function";
}

std::string_view function_short_name(std::uint8_t function) {
  const auto* f = find_function(function & 0x7FU);
  if (f != nullptr) return f->short_name;
  if (is_user_defined_function(function & 0x7FU)) return "user fc";
  return "unknown fc";
}

std::string_view exception_name(std::uint8_t code) {
  switch (code) {
    case 0x01: return "ILLEGAL FUNCTION";
    case 0x02: return "ILLEGAL DATA ADDRESS";
    case 0x03: return "ILLEGAL DATA VALUE";
    case 0x04: return "SERVER DEVICE FAILURE";
    case 0x05: return "ACKNOWLEDGE";
    case 0x06: return "SERVER DEVICE BUSY";
    case 0x07: return "NEGATIVE ACKNOWLEDGE";  // legacy Modicon PI-MBUS-300
    case 0x08: return "MEMORY PARITY ERROR";
    case 0x0A: return "GATEWAY PATH UNAVAILABLE";
    case 0x0B: return "GATEWAY TARGET DEVICE FAILED TO RESPOND";
    default: return "UNKNOWN EXCEPTION";
  }
}

}  // namespace rtu
