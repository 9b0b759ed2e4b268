// The device-map loader: the bundled maps load, and each kind of mistake in a map is
// reported as "file:line: what is wrong".
#include <gtest/gtest.h>

#include <string>

#include "dissect/map_library.hpp"
#include "dissect/map_loader.hpp"

namespace rtu::dissect {
namespace {

// A valid map; each test appends or changes one thing. Line numbers matter below.
constexpr const char* kBase = R"([device]
model = "bad"
name = "test device"

[var.PT]
default = 1

[space.regs]
functions = [3, 6, 16]

[[space.regs.point]]
addr = 0x0000
name = "PT"
type = "u32"
learn = "PT"
)";
// kBase has 15 lines; the first appended line is line 16.

std::vector<std::string> errors_of(const std::string& text) {
  return load_map_text(text, "bad.toml").errors;
}

TEST(MapLoader, BaseMapLoads) {
  const auto r = load_map_text(kBase, "bad.toml");
  ASSERT_TRUE(r.ok()) << r.errors.front();
  ASSERT_EQ(r.map.spaces.size(), 1U);
  EXPECT_EQ(r.map.spaces[0].points[0].learn, std::optional<std::size_t>(0));
}

TEST(MapLoader, BundledMapsLoad) {
  MapLibrary lib;
  const auto errors = lib.load_dir(RTUSCOPE_SOURCE_DIR "/dissectors");
  for (const auto& e : errors) ADD_FAILURE() << e;
  EXPECT_EQ(lib.model_list(), "th900, yakotec, yw2050, yw2300");
}

TEST(MapLoader, UnknownKey) {
  const auto e = errors_of(std::string(kBase) + R"(
[[space.regs.point]]
addr = 0x0002
name = "Ua"
scal = 0.01
)");
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0],
            "bad.toml:20: unknown key 'scal' in point 'Ua' (allowed: addr, name, type, "
            "word_order, access, scale, offset, unit, decimals, scale_by, learn, enum, bits, "
            "range, spare, device_class, state_class, doc)");
}

TEST(MapLoader, UnknownTopLevelTable) {
  const auto e = errors_of(std::string(kBase) + "\n[points]\nx = 1\n");
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0],
            "bad.toml:17: unknown key 'points' in the top level (allowed: device, space, "
            "var, exceptions)");
}

TEST(MapLoader, OverlappingPoints) {
  // PT is 32 bits at 0x0000-0x0001: a point at 0x0001 overlaps it.
  const auto e = errors_of(std::string(kBase) + R"(
[[space.regs.point]]
addr = 0x0001
name = "Ua"
)");
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0],
            "bad.toml:17: point 'Ua' at 0x0001 overlaps point 'PT' (0x0000..0x0001, "
            "line 11)");
}

TEST(MapLoader, SpareRegistersCountInOverlaps) {
  const auto e = errors_of(std::string(kBase) + R"(
[[space.regs.point]]
addr = 0x0002
name = "SV"
spare = 1

[[space.regs.point]]
addr = 0x0003
name = "SV1"
)");
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0],
            "bad.toml:22: point 'SV1' at 0x0003 overlaps point 'SV' (0x0002..0x0003, "
            "line 17)");
}

TEST(MapLoader, DanglingScaleByReference) {
  const auto e = errors_of(std::string(kBase) + R"(
[[space.regs.point]]
addr = 0x0002
name = "Ia"
scale_by = ["CT"]
)");
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0], "bad.toml:20: point 'Ia': scale_by refers to 'CT', which no [var.CT] declares");
}

TEST(MapLoader, DanglingLearnReference) {
  const auto e = errors_of(std::string(kBase) + R"(
[[space.regs.point]]
addr = 0x0002
name = "CT"
learn = "CT"
)");
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0], "bad.toml:20: point 'CT': learn refers to 'CT', which no [var.CT] declares");
}

TEST(MapLoader, VarNeverLearned) {
  const auto e = errors_of(std::string(kBase) + "\n[var.CT]\ndefault = 1\n");
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0], "bad.toml:17: [var.CT] is never learned: no point has learn = \"CT\"");
}

TEST(MapLoader, BadValues) {
  const auto e = errors_of(std::string(kBase) + R"(
[[space.regs.point]]
addr = 0x10000
name = "A"

[[space.regs.point]]
addr = 0x0010
name = "B"
type = "u17"

[[space.regs.point]]
addr = 0x0011
name = "C"
range = [5, 1]

[[space.regs.point]]
addr = 0x0012
name = "D"
word_order = "lo_hi"

[[space.regs.point]]
addr = 0x0013
name = "E"
type = "u8"

[[space.regs.point]]
addr = 0x0014
name = "F"
scale = 0
)");
  const std::vector<std::string> expected = {
      "bad.toml:18: point 'A': 'addr' = 65536 is outside 0..65535",
      "bad.toml:24: point 'B': type 'u17' is not one of: u8, i8, u16, i16, u32, i32, f32, bit",
      "bad.toml:29: point 'C': range must be [min, max] with min <= max",
      "bad.toml:34: point 'D': word_order applies to 32-bit types only",
      "bad.toml:39: point 'E': type 'u8' needs a byte-addressed space (addressing = \"byte\")",
      "bad.toml:44: point 'F': scale must not be 0",
  };
  EXPECT_EQ(e, expected);
}

TEST(MapLoader, HomeAssistantClassesOfAPoint) {
  const auto r = load_map_text(std::string(kBase) + R"(
[[space.regs.point]]
addr = 0x0002
name = "PF"
device_class = "power_factor"
state_class = "measurement"

[[space.regs.point]]
addr = 0x0003
name = "RA"
unit = "A"
state_class = ""

[[space.regs.point]]
addr = 0x0004
name = "Ua"
unit = "V"
)",
                               "bad.toml");
  ASSERT_TRUE(r.ok()) << r.errors.front();
  const auto& points = r.map.spaces[0].points;
  ASSERT_EQ(points.size(), 4U);
  EXPECT_EQ(points[1].device_class, std::optional<std::string>("power_factor"));
  EXPECT_EQ(points[1].state_class, std::optional<std::string>("measurement"));
  // "" is kept apart from "not said": it takes away the unit's class.
  EXPECT_EQ(points[2].device_class, std::nullopt);
  EXPECT_EQ(points[2].state_class, std::optional<std::string>(""));
  EXPECT_EQ(points[3].device_class, std::nullopt);
  EXPECT_EQ(points[3].state_class, std::nullopt);
}

TEST(MapLoader, BadHomeAssistantClassesSayWhere) {
  const auto e = errors_of(std::string(kBase) + R"(
[[space.regs.point]]
addr = 0x0002
name = "E"
unit = "kWh"
state_class = "increasing"

[[space.regs.point]]
addr = 0x0003
name = "U"
device_class = "Voltage"
state_class = 1
)");
  const std::vector<std::string> expected = {
      "bad.toml:21: point 'E': state_class 'increasing' is not one of: measurement, total, "
      "total_increasing (or \"\" for none)",
      "bad.toml:26: point 'U': device_class 'Voltage' must be a Home Assistant sensor device "
      "class, lowercase letters, digits and '_' (e.g. \"voltage\"), or \"\" for none",
      "bad.toml:27: point 'U': 'state_class' must be a string",
  };
  EXPECT_EQ(e, expected);
}

TEST(MapLoader, FunctionInTwoSpacesAndMixedKinds) {
  const auto e = errors_of(std::string(kBase) + R"(
[space.more]
functions = [3]

[space.mixed]
functions = [1, 4]
)");
  const std::vector<std::string> expected = {
      "bad.toml:18: [space.more]: function 3 already addresses another space",
      "bad.toml:21: [space.mixed]: functions mix bit (1, 2, 5, 15) and register (3, 4, 6, 16) "
      "codes",
  };
  EXPECT_EQ(e, expected);
}

TEST(MapLoader, OnlyTheEightClassicDataFunctions) {
  // FC22 and FC23 address holding registers too, but a map cannot list them; nor FC07.
  const auto e = errors_of(std::string(kBase) + R"(
[space.other]
functions = [22, 23, 7, 259]
)");
  const std::vector<std::string> expected = {
      "bad.toml:18: [space.other]: functions: 22 is not one of 1, 2, 3, 4, 5, 6, 15, 16",
      "bad.toml:18: [space.other]: functions: 23 is not one of 1, 2, 3, 4, 5, 6, 15, 16",
      "bad.toml:18: [space.other]: functions: 7 is not one of 1, 2, 3, 4, 5, 6, 15, 16",
      "bad.toml:18: [space.other]: functions: 259 is not one of 1, 2, 3, 4, 5, 6, 15, 16",
  };
  EXPECT_EQ(e, expected);
}

TEST(MapLoader, BitFieldsMustFitAndNotOverlap) {
  const auto e = errors_of(std::string(kBase) + R"(
[[space.regs.point]]
addr = 0x0002
name = "CTRL"
bits = [
  { bit = 0, name = "dir" },
  { bit = 0, name = "again" },
  { bit = 15, width = 2, name = "wide" },
]
)");
  const std::vector<std::string> expected = {
      "bad.toml:22: point 'CTRL': bits entry: bit 0 overlaps field 'dir'",
      "bad.toml:23: point 'CTRL': bits entry: bits 15..16 do not fit a 16-bit value",
  };
  EXPECT_EQ(e, expected);
}

TEST(MapLoader, MissingDeviceAndSpaces) {
  const auto e = errors_of("[var.PT]\ndefault = 1\n");
  const std::vector<std::string> expected = {
      "bad.toml:1: missing table [device]",
      "bad.toml:1: missing [space.<id>] tables: a map needs at least one address space",
      "bad.toml:1: [var.PT] is never learned: no point has learn = \"PT\"",
  };
  EXPECT_EQ(e, expected);
}

TEST(MapLoader, TomlSyntaxErrorHasItsLine) {
  const auto e = errors_of("[device]\nmodel = \"x\"\nname = \n");
  ASSERT_EQ(e.size(), 1U);
  EXPECT_TRUE(e[0].starts_with("bad.toml:3: ")) << e[0];
}

TEST(MapLoader, ModelMustMatchFileName) {
  const std::string path = ::testing::TempDir() + "/other.toml";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs(kBase, f);
    std::fclose(f);
  }
  const auto r = load_map_file(path);
  ASSERT_EQ(r.errors.size(), 1U);
  EXPECT_EQ(r.errors[0], path + ":1: [device] model 'bad' differs from the file name 'other.toml'");
}

TEST(BusFile, ReadsLineAndSlaves) {
  const auto bus = load_bus_text(
      "[line]\nbaud = 19200\nparity = \"N\"\nstop = 2\n\n[slaves]\n1 = \"yw2050\"\n7 = \"th900\"\n",
      "plant.toml");
  EXPECT_EQ(bus.baud, std::optional<std::uint32_t>(19200));
  EXPECT_EQ(bus.parity, std::optional<Parity>(Parity::kNone));
  EXPECT_EQ(bus.stop_bits, std::optional<std::uint8_t>(2));
  ASSERT_EQ(bus.slaves.size(), 2U);
  EXPECT_EQ(bus.slaves[1].slave, 7);
  EXPECT_EQ(bus.slaves[1].model, "th900");
}

TEST(BusFile, BadSlaveAddressSaysWhere) {
  try {
    load_bus_text("[slaves]\n1 = \"yw2050\"\n300 = \"th900\"\n", "plant.toml");
    FAIL() << "expected an InputError";
  } catch (const std::exception& e) {
    EXPECT_STREQ(e.what(), "plant.toml:3: [slaves]: '300' is not a slave address 1..247");
  }
}

// point_at() answers from an address table built at load: for every address of every space
// of the bundled maps (and beyond their ends) it names the one point whose extent, spare
// registers included, holds the address, as a scan of the points by that definition does.
TEST(MapLoader, PointAtAgreesWithAScanOfThePointsOnEveryBundledMap) {
  MapLibrary library;
  ASSERT_TRUE(library.load_dir(RTUSCOPE_SOURCE_DIR "/dissectors").empty());
  ASSERT_FALSE(library.maps().empty());
  std::size_t hits = 0;
  for (const auto& map : library.maps()) {
    for (const Space& space : map->spaces) {
      ASSERT_FALSE(space.points.empty());
      const std::uint32_t end =
          space.points.back().addr + space.points.back().units(space.addressing);
      for (std::uint32_t a = 0; a < end + 64; ++a) {
        const Point* scanned = nullptr;
        for (const Point& p : space.points) {
          if (a >= p.addr && a < p.addr + p.units(space.addressing)) scanned = &p;
        }
        ASSERT_EQ(space.point_at(a), scanned) << map->model << " " << space.id << " " << a;
        if (scanned != nullptr) ++hits;
      }
      EXPECT_EQ(space.point_at(0xFFFFFFFFU), nullptr);
    }
  }
  EXPECT_GT(hits, 100U);
}

// space_for() answers from a table built at load: for every function code of every bundled
// map it names the space that lists the code, as a scan of the spaces does; a copy of a map
// whose spaces then change answers from the spaces it has, not from the table.
TEST(MapLoader, SpaceForAgreesWithAScanOfTheSpacesOnEveryBundledMap) {
  MapLibrary library;
  ASSERT_TRUE(library.load_dir(RTUSCOPE_SOURCE_DIR "/dissectors").empty());
  std::size_t served = 0;
  for (const auto& map : library.maps()) {
    for (int code = 0; code < 256; ++code) {
      const auto function = static_cast<std::uint8_t>(code);
      const Space* scanned = nullptr;
      for (const Space& space : map->spaces) {
        if (scanned == nullptr && space.serves(function)) scanned = &space;
      }
      ASSERT_EQ(map->space_for(function), scanned) << map->model << " function " << code;
      if (scanned != nullptr) ++served;
    }
  }
  EXPECT_GT(served, 8U);

  DeviceMap changed = *library.maps().front();
  Space extra;
  extra.id = "extra";
  extra.functions = {100};
  changed.spaces.push_back(extra);
  ASSERT_NE(changed.space_for(100), nullptr);
  EXPECT_EQ(changed.space_for(100)->id, "extra");
  EXPECT_EQ(changed.space_for(3), &changed.spaces[0]) << "not the original map's space";
}

// defined_in() counts per point what point_at() says per address, over ranges that start
// and end inside points, between them, before the first and past the last (identification
// asks it for every request's range, up to 65,535 registers).
TEST(MapLoader, DefinedInCountsTheAddressesPointAtFindsOnEveryBundledMap) {
  MapLibrary library;
  ASSERT_TRUE(library.load_dir(RTUSCOPE_SOURCE_DIR "/dissectors").empty());
  std::uint64_t compared = 0;
  for (const auto& map : library.maps()) {
    for (const Space& space : map->spaces) {
      const std::uint32_t end =
          space.points.back().addr + space.points.back().units(space.addressing);
      std::vector<std::uint32_t> defined_before(end + 70, 0);  // prefix sums of point_at
      for (std::uint32_t a = 0; a + 1 < defined_before.size(); ++a) {
        defined_before[a + 1] = defined_before[a] + (space.point_at(a) != nullptr ? 1 : 0);
      }
      const std::uint32_t last = static_cast<std::uint32_t>(defined_before.size() - 1);
      for (std::uint32_t begin = 0; begin <= last; begin += 3) {
        for (std::uint32_t stop = begin; stop <= last; stop += 7) {
          ASSERT_EQ(space.defined_in(begin, stop), defined_before[stop] - defined_before[begin])
              << map->model << " " << space.id << " [" << begin << ", " << stop << ")";
          ++compared;
        }
      }
      EXPECT_EQ(space.defined_in(5, 5), 0U);
      EXPECT_EQ(space.defined_in(9, 2), 0U);
    }
  }
  EXPECT_GT(compared, 1000U);
}

// A space whose points changed after it was indexed searches them instead of a stale table.
TEST(MapLoader, PointAtFollowsPointsAddedAfterIndexing) {
  auto r = load_map_text(kBase, "bad.toml");
  ASSERT_TRUE(r.ok());
  Space& space = r.map.spaces[0];
  EXPECT_EQ(space.point_at(0x10), nullptr);
  Point extra;
  extra.addr = 0x10;
  extra.type = PointType::kU16;
  space.points.push_back(extra);
  EXPECT_EQ(space.point_at(0x10), &space.points.back());
  EXPECT_EQ(space.point_at(0x01), &space.points.front());
}

}  // namespace
}  // namespace rtu::dissect
