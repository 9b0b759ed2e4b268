#include "adu.hpp"

#include "core/crc16.hpp"

namespace rtu::sim {

AduBuilder& AduBuilder::u8(std::uint8_t v) {
  bytes_.push_back(v);
  return *this;
}

AduBuilder& AduBuilder::u16(std::uint16_t v) {
  bytes_.push_back(static_cast<std::uint8_t>(v >> 8U));
  bytes_.push_back(static_cast<std::uint8_t>(v & 0xFFU));
  return *this;
}

AduBuilder& AduBuilder::raw(std::span<const std::uint8_t> v) {
  bytes_.insert(bytes_.end(), v.begin(), v.end());
  return *this;
}

AduBuilder& AduBuilder::words(std::span<const std::uint16_t> v) {
  for (const std::uint16_t w : v) u16(w);
  return *this;
}

Bytes AduBuilder::seal() {
  const std::uint16_t crc = crc16(bytes_);
  bytes_.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  bytes_.push_back(static_cast<std::uint8_t>(crc >> 8U));
  return std::move(bytes_);
}

void reseal(Bytes& adu) {
  if (adu.size() < 2) return;
  const std::uint16_t crc = crc16(std::span(adu).first(adu.size() - 2));
  adu[adu.size() - 2] = static_cast<std::uint8_t>(crc & 0xFFU);
  adu[adu.size() - 1] = static_cast<std::uint8_t>(crc >> 8U);
}

Bytes read_request(std::uint8_t slave, std::uint8_t function, std::uint16_t address,
                   std::uint16_t quantity) {
  return AduBuilder(slave, function).u16(address).u16(quantity).seal();
}

Bytes registers_response(std::uint8_t slave, std::uint8_t function,
                         std::span<const std::uint16_t> values) {
  return AduBuilder(slave, function)
      .u8(static_cast<std::uint8_t>(values.size() * 2))
      .words(values)
      .seal();
}

Bytes registers_response(std::uint8_t slave, std::uint8_t function,
                         std::initializer_list<std::uint16_t> values) {
  return registers_response(slave, function, std::span(values.begin(), values.size()));
}

Bytes bits_response(std::uint8_t slave, std::uint8_t function, std::uint32_t bits,
                    std::uint16_t quantity) {
  AduBuilder b(slave, function);
  const auto count = static_cast<std::uint8_t>((quantity + 7U) / 8U);
  b.u8(count);
  for (unsigned i = 0; i < count; ++i) {
    std::uint32_t byte = (bits >> (8U * i)) & 0xFFU;
    // Unused high bits of the last byte are zero (V1.1b3 §6.1).
    const unsigned used = quantity - 8U * i;
    if (used < 8U) byte &= (1U << used) - 1U;
    b.u8(static_cast<std::uint8_t>(byte));
  }
  return b.seal();
}

Bytes write_single(std::uint8_t slave, std::uint8_t function, std::uint16_t address,
                   std::uint16_t value) {
  return AduBuilder(slave, function).u16(address).u16(value).seal();
}

Bytes write_multiple_request(std::uint8_t slave, std::uint16_t address,
                             std::span<const std::uint16_t> values) {
  return AduBuilder(slave, 0x10)
      .u16(address)
      .u16(static_cast<std::uint16_t>(values.size()))
      .u8(static_cast<std::uint8_t>(values.size() * 2))
      .words(values)
      .seal();
}

Bytes write_multiple_request(std::uint8_t slave, std::uint16_t address,
                             std::initializer_list<std::uint16_t> values) {
  return write_multiple_request(slave, address, std::span(values.begin(), values.size()));
}

Bytes write_multiple_response(std::uint8_t slave, std::uint16_t address, std::uint16_t quantity) {
  return AduBuilder(slave, 0x10).u16(address).u16(quantity).seal();
}

Bytes exception_response(std::uint8_t slave, std::uint8_t function, std::uint8_t code) {
  return AduBuilder(slave, static_cast<std::uint8_t>(function | 0x80U)).u8(code).seal();
}

}  // namespace rtu::sim
