// Fuzz target for the device-map loader (dissect/map_loader.hpp, load_map_text): the input
// is the TOML text of a map.
//
// Oracles: the loader throws nothing; every error reads "fuzz-map.toml:LINE: ..." with a
// line of the input, in file order, and loading again gives the same errors. A map it
// accepts keeps the promises the device stage relies on: a model key, at least one space,
// each function code in one space only and of the space's kind, points sorted, disjoint,
// named uniquely and inside 0..0xFFFF, found again by point_at(); a scale that is not 0,
// 0..9 decimals, var references that exist, bit fields inside the value and disjoint,
// min ≤ max, and every var learned by some point. The register decoder's split of ranges
// around its points (register_plans.hpp) covers each range's bytes once, in order, with a
// whole value only where a point starts and as long as the point's value.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include "dissect/map_loader.hpp"
#include "dissect/register_plans.hpp"
#include "fuzz_oracle.hpp"

namespace {

using rtu::dissect::DeviceMap;
using rtu::dissect::Point;
using rtu::dissect::Space;
using rtu::fuzz::fail;

constexpr std::string_view kTarget = "fuzz_device_map";
constexpr std::string_view kFile = "fuzz-map.toml";

void check_point(const DeviceMap& map, const Space& space, const Point& p) {
  if (p.name.empty()) fail(kTarget, "accepted a point without a name", "");
  if (p.addr + p.units(space.addressing) > 0x10000) fail(kTarget, "point past 0xFFFF", p.name);
  if (space.point_at(p.addr) != &p) fail(kTarget, "point_at() does not find the point", p.name);
  if (p.scale == 0.0 || !std::isfinite(p.scale) || !std::isfinite(p.offset)) {
    fail(kTarget, "accepted a zero or infinite scale or offset", p.name);
  }
  if (p.decimals < 0 || p.decimals > 9) fail(kTarget, "decimals outside 0..9", p.name);
  for (const std::size_t v : p.scale_by) {
    if (v >= map.vars.size()) fail(kTarget, "scale_by refers past the vars", p.name);
  }
  if (p.learn && *p.learn >= map.vars.size()) fail(kTarget, "learn refers past the vars", p.name);
  if (p.min && p.max && *p.min > *p.max) fail(kTarget, "range with min > max", p.name);
  const unsigned width = p.value_bytes() * 8;
  for (std::size_t i = 0; i < p.bits.size(); ++i) {
    const auto& f = p.bits[i];
    if (f.width == 0 || static_cast<unsigned>(f.bit + f.width) > width)
      fail(kTarget, "bit field outside the value", f.name);
    for (std::size_t k = 0; k < i; ++k) {
      const auto& g = p.bits[k];
      if (f.bit < g.bit + g.width && g.bit < f.bit + f.width) {
        fail(kTarget, "bit fields overlap", f.name);
      }
    }
  }
}

void check_space(const DeviceMap& map, const Space& space) {
  if (space.functions.empty()) fail(kTarget, "accepted a space without functions", space.id);
  for (const auto fc : space.functions) {
    if (map.space_for(fc) != &space) fail(kTarget, "function in two spaces", space.id);
  }
  for (std::size_t i = 0; i < space.points.size(); ++i) {
    const Point& p = space.points[i];
    if (i > 0) {
      const Point& prev = space.points[i - 1];
      if (prev.addr + prev.units(space.addressing) > p.addr)
        fail(kTarget, "points overlap", p.name);
    }
    for (std::size_t k = 0; k < i; ++k) {
      if (space.points[k].name == p.name) fail(kTarget, "point name used twice", p.name);
    }
    check_point(map, space, p);
  }
}

// Ranges starting one unit before, at and after each of the first points, from one byte to
// a few bytes past the point's value.
void check_register_splits(const Space& space) {
  constexpr std::size_t kPointsChecked = 16;
  std::vector<rtu::dissect::RegisterStep> steps;
  for (std::size_t i = 0; i < space.points.size() && i < kPointsChecked; ++i) {
    const Point& p = space.points[i];
    for (std::uint32_t start = p.addr > 0 ? p.addr - 1 : 0; start <= p.addr + 1; ++start) {
      for (std::size_t bytes = 1; bytes <= p.value_bytes() + 3; ++bytes) {
        rtu::dissect::plan_registers(space, start, bytes, steps);
        std::size_t next = 0;
        for (const auto& step : steps) {
          if (step.offset != next || step.length == 0) fail(kTarget, "split leaves a gap", p.name);
          const bool value = step.kind == rtu::dissect::RegisterStep::Kind::kValue;
          if (value && (step.point->addr != step.addr || step.length != step.point->value_bytes()))
            fail(kTarget, "split gives a value that is not its point's", p.name);
          if ((step.point == nullptr) !=
              (step.kind == rtu::dissect::RegisterStep::Kind::kUndefined))
            fail(kTarget, "split names no point for a defined address", p.name);
          next += step.length;
        }
        if (next != bytes) fail(kTarget, "split does not cover the range", p.name);
      }
    }
  }
}

void check_map(const DeviceMap& map) {
  if (map.model.empty()) fail(kTarget, "accepted a map without a model", "");
  if (map.spaces.empty()) fail(kTarget, "accepted a map without spaces", "");
  for (const auto& space : map.spaces) {
    check_space(map, space);
    check_register_splits(space);
  }
  for (std::size_t v = 0; v < map.vars.size(); ++v) {
    bool learned = false;
    for (const auto& space : map.spaces) {
      for (const auto& p : space.points) learned = learned || p.learn == v;
    }
    if (!learned) fail(kTarget, "accepted a var no point learns", map.vars[v].name);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  rtu::dissect::MapLoadResult result;
  std::vector<std::string> again;
  try {
    result = rtu::dissect::load_map_text(text, kFile);
    again = rtu::dissect::load_map_text(text, kFile).errors;
  } catch (const std::exception& e) {
    fail(kTarget, "the loader threw", e.what());
  }
  if (again != result.errors) fail(kTarget, "errors differ between two loads", "");
  const std::uint64_t lines = rtu::fuzz::count_lines(text);
  std::uint64_t previous_line = 0;
  for (const auto& error : result.errors) {
    rtu::fuzz::require_line(kTarget, error, kFile, lines);
    const std::uint64_t line = rtu::fuzz::place_in_message(error, kFile)->number;
    if (line < previous_line) fail(kTarget, "errors not in file order", error);
    previous_line = line;
  }
  if (result.ok()) check_map(result.map);
  return 0;
}
