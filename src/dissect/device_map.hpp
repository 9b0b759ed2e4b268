#pragma once
// A device model's register map, as loaded from a dissectors/*.toml file (map_loader.hpp;
// the format is documented in dissectors/README.md). Plain data: no TOML types leak here,
// so only the loader's translation unit pays for parsing.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rtu::dissect {

// Value types of a point. u8/i8 exist only in byte-addressed register spaces, bit only in
// coil / discrete-input spaces.
enum class PointType : std::uint8_t { kU8, kI8, kU16, kI16, kU32, kI32, kF32, kBit };

// Order of the two 16-bit words of a 32-bit value on the wire (bytes inside a word are
// always big-endian, Modbus Application Protocol §4.2).
enum class WordOrder : std::uint8_t { kHighFirst, kLowFirst };

enum class Access : std::uint8_t { kReadWrite, kReadOnly, kWriteOnly };

// Registers (FC03/04/06/16) or single bits (FC01/02/05/15).
enum class SpaceKind : std::uint8_t { kRegisters, kBits };

// kWord: register k of a transfer starting at A has address A + k (the Modbus norm).
// kByte: the address counts bytes, so register k sits at A + 2k and a one-byte point may
// sit at an odd address (YW2050).
enum class Addressing : std::uint8_t { kWord, kByte };

struct BitField {
  std::uint8_t bit = 0;    // lowest bit of the field, 0 = least significant
  std::uint8_t width = 1;  // bits
  std::string name;
  std::string doc;
};

struct EnumEntry {
  std::int64_t value = 0;
  std::string text;
};

struct Point {
  // What decoding a value and handing it on read comes first, in three cache lines where it
  // was spread over four: the device stage reads these for every value a frame carries (a
  // point is over 300 bytes).
  std::uint32_t addr = 0;  // in the space's addressing unit
  PointType type = PointType::kU16;
  WordOrder word_order = WordOrder::kHighFirst;  // 32-bit types only
  Access access = Access::kReadWrite;
  // Registers that follow the point, travel with it, and carry no documented meaning
  // (TH900 "type 3" points): shown raw, flagged when not zero.
  std::uint16_t spare = 0;
  int decimals = 0;  // digits shown after the point
  double scale = 1.0;
  double offset = 0.0;
  std::optional<double> min;  // documented range of raw × scale + offset
  std::optional<double> max;
  std::optional<std::size_t> learn;   // index into DeviceMap::vars this point sets
  std::vector<std::size_t> scale_by;  // indices into DeviceMap::vars, multiplied in
  std::string name;
  std::string unit;
  std::vector<EnumEntry> enums;
  std::vector<BitField> bits;
  // Home Assistant classes for MQTT discovery where the map states them. Unset: the unit's
  // (dissectors/home_assistant/sensor_classes.toml); "": none, whatever the unit says.
  // state_class, when set and not empty, is measurement, total or total_increasing.
  std::optional<std::string> device_class;
  std::optional<std::string> state_class;
  std::string doc;
  std::uint32_t line = 0;  // where it was defined, for messages

  [[nodiscard]] bool is_signed() const {
    return type == PointType::kI8 || type == PointType::kI16 || type == PointType::kI32;
  }
  // Bytes of the value itself (a bit point: 0).
  [[nodiscard]] std::uint32_t value_bytes() const;
  // Address units the value occupies, spare registers excluded.
  [[nodiscard]] std::uint32_t value_units(Addressing addressing) const;
  // Address units including the spare registers.
  [[nodiscard]] std::uint32_t units(Addressing addressing) const;
};

struct Space {
  std::string id;
  SpaceKind kind = SpaceKind::kRegisters;
  Addressing addressing = Addressing::kWord;
  std::vector<std::uint8_t> functions;
  std::vector<Point> points;  // sorted by address, not overlapping
  std::string doc;

  [[nodiscard]] bool serves(std::uint8_t function) const;
  // The point whose extent (spare included) contains `addr`, or null.
  [[nodiscard]] const Point* point_at(std::uint32_t addr) const;
  // The first point that starts at or after `addr`, or null.
  [[nodiscard]] const Point* point_from(std::uint32_t addr) const;
  // How many addresses of [begin, end) some point's extent contains: point_at() != null for
  // each, counted per point rather than per address (a request may span 65,535 registers).
  [[nodiscard]] std::uint32_t defined_in(std::uint32_t begin, std::uint32_t end) const;

  // Builds the address table point_at() answers from: every value a frame carries is looked
  // up there, and a search through the (large) points costs more than decoding the value.
  // Call once `points` is final; until then, and whenever `points` has changed size since,
  // point_at() searches instead.
  void index_points();

 private:
  // Too wide a span of addresses (a map with points far apart) keeps the search.
  static constexpr std::uint32_t kMaxIndexedSpan = 1U << 17U;
  [[nodiscard]] const Point* search_point_at(std::uint32_t addr) const;
  // slot_by_addr_[a - index_base_]: 1 + the index in `points` of the point covering a, or 0.
  std::vector<std::uint16_t> slot_by_addr_;
  std::uint32_t index_base_ = 0;
  std::size_t indexed_points_ = 0;  // points.size() when the table was built
};

// Inline: the register decoder asks these for every value a frame carries.
inline std::uint32_t Point::value_bytes() const {
  switch (type) {
    case PointType::kU8:
    case PointType::kI8: return 1;
    case PointType::kU16:
    case PointType::kI16: return 2;
    case PointType::kU32:
    case PointType::kI32:
    case PointType::kF32: return 4;
    case PointType::kBit: return 0;
  }
  return 0;
}

inline std::uint32_t Point::value_units(Addressing addressing) const {
  if (type == PointType::kBit) return 1;
  if (addressing == Addressing::kByte) return value_bytes();
  return (value_bytes() + 1) / 2;
}

inline std::uint32_t Point::units(Addressing addressing) const {
  const std::uint32_t spare_units = addressing == Addressing::kByte ? 2U * spare : spare;
  return value_units(addressing) + spare_units;
}

inline const Point* Space::point_at(std::uint32_t addr) const {
  if (indexed_points_ != points.size() || indexed_points_ == 0) return search_point_at(addr);
  const std::uint32_t rel = addr - index_base_;  // below the base wraps to beyond the table
  if (rel >= slot_by_addr_.size()) return nullptr;
  const std::uint16_t slot = slot_by_addr_[rel];
  return slot == 0 ? nullptr : &points[slot - 1U];
}

// A value learned from the traffic (e.g. a PT ratio) that other points scale by.
struct Var {
  std::string name;
  std::optional<double> default_value;  // the manual's factory default, if any
  std::string doc;
};

struct VendorException {
  std::uint8_t code = 0;
  std::string name;
};

struct DeviceMap {
  std::string model;  // key used by --device ADDR=MODEL
  std::string name;
  std::string vendor;
  std::string manual;
  std::string doc;
  std::string source_file;
  std::vector<Space> spaces;
  std::vector<Var> vars;
  std::vector<VendorException> exceptions;  // replace the standard meanings when present

  // The space a function code addresses, or null when the map does not list it.
  [[nodiscard]] const Space* space_for(std::uint8_t function) const;
  // The vendor's name for an exception code, or empty.
  [[nodiscard]] std::string_view exception_name(std::uint8_t code) const;

  // Builds the table space_for() answers from: the register decoder and the identification
  // ask it of every frame, and a search through each space's functions cost about 40
  // instructions. Call once `spaces` is final; until then, and whenever `spaces` has changed
  // size since, space_for() searches instead.
  void index_spaces();

 private:
  [[nodiscard]] const Space* search_space_for(std::uint8_t function) const;
  // space_slot_[fc]: 1 + the index in `spaces` of the space serving fc, or 0.
  std::array<std::uint8_t, 256> space_slot_{};
  std::size_t indexed_spaces_ = 0;  // spaces.size() when the table was built
};

std::string_view point_type_name(PointType type);

}  // namespace rtu::dissect
