#include "dissect/device_map.hpp"

#include <algorithm>

namespace rtu::dissect {

bool Space::serves(std::uint8_t function) const {
  return std::find(functions.begin(), functions.end(), function) != functions.end();
}

void Space::index_points() {
  slot_by_addr_.clear();
  indexed_points_ = 0;
  if (points.empty() || points.size() >= UINT16_MAX) return;
  const std::uint32_t first = points.front().addr;
  const Point& last = points.back();
  const std::uint64_t span = std::uint64_t{last.addr} + last.units(addressing) - first;
  if (span > kMaxIndexedSpan) return;
  slot_by_addr_.assign(static_cast<std::size_t>(span), 0);
  index_base_ = first;
  // Filled from the search itself, so the table answers exactly as it does.
  for (std::uint32_t rel = 0; rel < slot_by_addr_.size(); ++rel) {
    const Point* p = search_point_at(first + rel);
    if (p != nullptr) slot_by_addr_[rel] = static_cast<std::uint16_t>(p - points.data() + 1);
  }
  indexed_points_ = points.size();
}

const Point* Space::search_point_at(std::uint32_t addr) const {
  // Points are sorted and disjoint: the candidate is the last one starting at or before addr.
  auto it = std::upper_bound(points.begin(), points.end(), addr,
                             [](std::uint32_t a, const Point& p) { return a < p.addr; });
  if (it == points.begin()) return nullptr;
  --it;
  return addr < it->addr + it->units(addressing) ? &*it : nullptr;
}

const Point* Space::point_from(std::uint32_t addr) const {
  auto it = std::lower_bound(points.begin(), points.end(), addr,
                             [](const Point& p, std::uint32_t a) { return p.addr < a; });
  return it == points.end() ? nullptr : &*it;
}

std::uint32_t Space::defined_in(std::uint32_t begin, std::uint32_t end) const {
  if (begin >= end) return 0;
  // The first point that ends after `begin`: points are sorted and disjoint, so their ends
  // are sorted too.
  auto it = std::upper_bound(
      points.begin(), points.end(), begin,
      [this](std::uint32_t a, const Point& p) { return a < p.addr + p.units(addressing); });
  std::uint32_t defined = 0;
  for (; it != points.end() && it->addr < end; ++it) {
    const std::uint32_t from = std::max(begin, it->addr);
    const std::uint32_t to = std::min(end, it->addr + it->units(addressing));
    if (from < to) defined += to - from;
  }
  return defined;
}

const Space* DeviceMap::space_for(std::uint8_t function) const {
  if (indexed_spaces_ != spaces.size() || indexed_spaces_ == 0) return search_space_for(function);
  const std::uint8_t slot = space_slot_[function];
  return slot == 0 ? nullptr : &spaces[slot - 1U];
}

const Space* DeviceMap::search_space_for(std::uint8_t function) const {
  for (const auto& space : spaces) {
    if (space.serves(function)) return &space;
  }
  return nullptr;
}

void DeviceMap::index_spaces() {
  space_slot_.fill(0);
  indexed_spaces_ = 0;
  if (spaces.empty() || spaces.size() >= UINT8_MAX) return;
  // Filled from the search itself, so the table answers exactly as it does.
  for (std::size_t function = 0; function < space_slot_.size(); ++function) {
    const Space* space = search_space_for(static_cast<std::uint8_t>(function));
    if (space != nullptr)
      space_slot_[function] = static_cast<std::uint8_t>(space - spaces.data() + 1);
  }
  indexed_spaces_ = spaces.size();
}

std::string_view DeviceMap::exception_name(std::uint8_t code) const {
  for (const auto& e : exceptions) {
    if (e.code == code) return e.name;
  }
  return {};
}

std::string_view point_type_name(PointType type) {
  switch (type) {
    case PointType::kU8: return "u8";
    case PointType::kI8: return "i8";
    case PointType::kU16: return "u16";
    case PointType::kI16: return "i16";
    case PointType::kU32: return "u32";
    case PointType::kI32: return "i32";
    case PointType::kF32: return "f32";
    case PointType::kBit: return "bit";
  }
  return "?";
}

}  // namespace rtu::dissect
