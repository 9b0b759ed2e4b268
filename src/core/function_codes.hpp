#pragma once
// Names of Modbus function codes and exception codes (MODBUS Application Protocol
// V1.1b3 §5, §6, §7).
#include <cstdint>
#include <string_view>

namespace rtu {

namespace fc {
inline constexpr std::uint8_t kReadCoils = 0x01;
inline constexpr std::uint8_t kReadDiscreteInputs = 0x02;
inline constexpr std::uint8_t kReadHoldingRegisters = 0x03;
inline constexpr std::uint8_t kReadInputRegisters = 0x04;
inline constexpr std::uint8_t kWriteSingleCoil = 0x05;
inline constexpr std::uint8_t kWriteSingleRegister = 0x06;
inline constexpr std::uint8_t kReadExceptionStatus = 0x07;
inline constexpr std::uint8_t kDiagnostics = 0x08;
inline constexpr std::uint8_t kGetCommEventCounter = 0x0B;
inline constexpr std::uint8_t kGetCommEventLog = 0x0C;
inline constexpr std::uint8_t kWriteMultipleCoils = 0x0F;
inline constexpr std::uint8_t kWriteMultipleRegisters = 0x10;
inline constexpr std::uint8_t kReportServerId = 0x11;
inline constexpr std::uint8_t kReadFileRecord = 0x14;
inline constexpr std::uint8_t kWriteFileRecord = 0x15;
inline constexpr std::uint8_t kMaskWriteRegister = 0x16;
inline constexpr std::uint8_t kReadWriteMultipleRegisters = 0x17;
inline constexpr std::uint8_t kReadFifoQueue = 0x18;
inline constexpr std::uint8_t kEncapsulatedInterface = 0x2B;
inline constexpr std::uint8_t kExceptionBit = 0x80;
}  // namespace fc

// True for the 19 public function codes this tool decodes field by field.
bool is_public_function(std::uint8_t function);
// User-defined ranges 65-72 and 100-110 (V1.1b3 §5).
bool is_user_defined_function(std::uint8_t function);

// Whether a request to address 0 (a broadcast) may carry `function`. A broadcast is never
// answered, so only writes make sense (MODBUS over Serial Line V1.02 §2.1): a public
// function that reads never is one. Writes, diagnostics (some sub-functions only act) and
// codes with no public meaning (a vendor's) may be.
bool may_be_broadcast(std::uint8_t function);

// "Read Holding Registers"; "Unknown function" for codes with no public meaning.
std::string_view function_name(std::uint8_t function);
// Short lowercase form for text output: "read holding".
std::string_view function_short_name(std::uint8_t function);

// "ILLEGAL DATA ADDRESS"; "UNKNOWN EXCEPTION" for codes with no standard meaning.
std::string_view exception_name(std::uint8_t code);

}  // namespace rtu
