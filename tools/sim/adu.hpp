#pragma once
// Building Modbus RTU ADUs (address + PDU + CRC) for the simulator, and the request and
// response shapes the device profiles share (MODBUS Application Protocol V1.1b3 §6).
#include <cstdint>
#include <initializer_list>
#include <span>
#include <vector>

namespace rtu::sim {

using Bytes = std::vector<std::uint8_t>;

// Appends fields big-endian, as Modbus does, then seals the frame with its CRC.
class AduBuilder {
 public:
  AduBuilder(std::uint8_t slave, std::uint8_t function) : bytes_{slave, function} {}

  AduBuilder& u8(std::uint8_t v);
  AduBuilder& u16(std::uint16_t v);
  AduBuilder& raw(std::span<const std::uint8_t> v);
  AduBuilder& words(std::span<const std::uint16_t> v);
  // Appends the CRC (low byte first) and hands the frame over.
  [[nodiscard]] Bytes seal();

 private:
  Bytes bytes_;
};

// Recomputes the CRC of a complete ADU in place (after an edit such as a new address).
void reseal(Bytes& adu);

// FC01/02/03/04 request: start address and quantity.
Bytes read_request(std::uint8_t slave, std::uint8_t function, std::uint16_t address,
                   std::uint16_t quantity);
// FC03/04 response: byte count then the register values.
Bytes registers_response(std::uint8_t slave, std::uint8_t function,
                         std::span<const std::uint16_t> values);
Bytes registers_response(std::uint8_t slave, std::uint8_t function,
                         std::initializer_list<std::uint16_t> values);
// FC01/02 response: `quantity` bits packed LSB first.
Bytes bits_response(std::uint8_t slave, std::uint8_t function, std::uint32_t bits,
                    std::uint16_t quantity);
// FC05/06 request, whose response is the same bytes (an echo).
Bytes write_single(std::uint8_t slave, std::uint8_t function, std::uint16_t address,
                   std::uint16_t value);
// FC10 request and its response (address and quantity).
Bytes write_multiple_request(std::uint8_t slave, std::uint16_t address,
                             std::span<const std::uint16_t> values);
Bytes write_multiple_request(std::uint8_t slave, std::uint16_t address,
                             std::initializer_list<std::uint16_t> values);
Bytes write_multiple_response(std::uint8_t slave, std::uint16_t address, std::uint16_t quantity);
// `function` without the exception bit; the response carries function | 0x80.
Bytes exception_response(std::uint8_t slave, std::uint8_t function, std::uint8_t code);

}  // namespace rtu::sim
