#pragma once
// Fixed-width integer access in a chosen byte order, for the binary capture formats.
// pcap and pcapng are written in the writer's order and read in either; the Upper-PDU
// TLVs and the RTAC serial header are always big-endian.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

namespace rtu {

enum class ByteOrder : std::uint8_t { kLittle, kBig };

constexpr ByteOrder host_byte_order() {
  return std::endian::native == std::endian::big ? ByteOrder::kBig : ByteOrder::kLittle;
}

// Reverses the bytes of an unsigned integer (std::byteswap is C++23).
template <typename T>
T swap_bytes(T value) {
  if constexpr (sizeof(T) == 1) {
    return value;
  } else if constexpr (sizeof(T) == 2) {
    return __builtin_bswap16(value);
  } else if constexpr (sizeof(T) == 4) {
    return __builtin_bswap32(value);
  } else {
    static_assert(sizeof(T) == 8);
    return __builtin_bswap64(value);
  }
}

// Reads sizeof(T) bytes at `p` as an unsigned integer. The caller has checked the bounds.
// One load and at most one byte swap: the binary readers do this for every field of every
// block, which a loop over the bytes made a visible part of reading a capture.
template <typename T>
T load(const std::uint8_t* p, ByteOrder order) {
  T value = 0;
  std::memcpy(&value, p, sizeof(T));
  return order == host_byte_order() ? value : swap_bytes(value);
}

inline std::uint16_t load_u16(std::span<const std::uint8_t> b, std::size_t at, ByteOrder o) {
  return load<std::uint16_t>(b.data() + at, o);
}
inline std::uint32_t load_u32(std::span<const std::uint8_t> b, std::size_t at, ByteOrder o) {
  return load<std::uint32_t>(b.data() + at, o);
}
inline std::uint64_t load_u64(std::span<const std::uint8_t> b, std::size_t at, ByteOrder o) {
  return load<std::uint64_t>(b.data() + at, o);
}

// Writes `value` as sizeof(T) bytes at `p` in `order`: one byte swap at most and one store,
// the mirror of load().
template <typename T>
void put(std::uint8_t* p, T value, ByteOrder order) {
  const T ordered = order == host_byte_order() ? value : swap_bytes(value);
  std::memcpy(p, &ordered, sizeof(T));
}

// Overwrites sizeof(T) bytes of `out` at `at` (for lengths known only after the body).
template <typename T>
void store(std::vector<std::uint8_t>& out, std::size_t at, T value, ByteOrder order) {
  put(out.data() + at, value, order);
}

// Appends `value` to `out` in `order`. The writers call it for every field of every block.
template <typename T>
void append(std::vector<std::uint8_t>& out, T value, ByteOrder order) {
  const std::size_t at = out.size();
  out.resize(at + sizeof(T));
  put(out.data() + at, value, order);
}

}  // namespace rtu
