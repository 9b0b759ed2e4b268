#pragma once
// Writes the fields of a binary record one after the other into a buffer sized for them
// beforehand. Exports write one pcapng block (and one Upper-PDU record) per frame, and their
// lengths are known before the first byte: sizing once and writing in place keeps the
// allocator out of every frame.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "capture/byte_order.hpp"

namespace rtu {

// `n` rounded up to a multiple of 4 (pcapng blocks and options, Upper-PDU tags).
constexpr std::size_t padded4(std::size_t n) {
  return (n + 3U) & ~std::size_t{3};
}

class FieldCursor {
 public:
  FieldCursor(std::uint8_t* at, ByteOrder order) : at_(at), order_(order) {}

  // An integer field in the cursor's byte order.
  template <typename T>
  void put(T value) {
    rtu::put(at_, value, order_);
    at_ += sizeof(T);
  }
  // `value`, then zeros up to `padded_length` bytes (never less than value.size()).
  void bytes(std::span<const std::uint8_t> value, std::size_t padded_length) {
    if (!value.empty()) std::memcpy(at_, value.data(), value.size());
    std::memset(at_ + value.size(), 0, padded_length - value.size());
    at_ += padded_length;
  }
  // A type-length-value field: 16-bit code, the 16-bit length `length_field`, then `value`
  // padded to `padded_length`. pcapng options state the value's length, Upper-PDU tags the
  // padded one.
  void tlv(std::uint16_t code, std::uint16_t length_field, std::span<const std::uint8_t> value,
           std::size_t padded_length) {
    put<std::uint16_t>(code);
    put<std::uint16_t>(length_field);
    bytes(value, padded_length);
  }
  [[nodiscard]] std::uint8_t* position() const { return at_; }

 private:
  std::uint8_t* at_;
  ByteOrder order_;
};

}  // namespace rtu
