#include "dissect/map_loader.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <span>
#include <sstream>

#include "core/function_codes.hpp"
#include "core/hex_digits.hpp"
#include "core/input_error.hpp"
#include "dissect/sensor_classes.hpp"
#include "modbus/data_access.hpp"

namespace rtu::dissect {
namespace {

using Keys = std::span<const std::string_view>;

constexpr std::string_view kTopKeys[] = {"device", "space", "var", "exceptions"};
constexpr std::string_view kDeviceKeys[] = {"model",  "name", "vendor",
                                            "manual", "doc",  "word_order"};
constexpr std::string_view kSpaceKeys[] = {"functions", "addressing", "doc", "point"};
constexpr std::string_view kVarKeys[] = {"default", "doc"};
constexpr std::string_view kPointKeys[] = {
    "addr",   "name",  "type",     "word_order",   "access",      "scale",
    "offset", "unit",  "decimals", "scale_by",     "learn",       "enum",
    "bits",   "range", "spare",    "device_class", "state_class", "doc"};
constexpr std::string_view kBitKeys[] = {"bit", "width", "name", "doc"};

std::string join(Keys keys) {
  std::string out;
  for (const auto k : keys) {
    if (!out.empty()) out += ", ";
    out += k;
  }
  return out;
}

// Home Assistant's device classes are snake_case words ("voltage", "power_factor"). The
// list grows with its releases, so only the spelling is checked: a typo such as "Voltage"
// is caught, an unknown class is left to Home Assistant.
bool is_device_class(std::string_view s) {
  if (s.empty() || s.front() == '_' || s.back() == '_') return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

bool is_model_key(std::string_view s) {
  if (s.empty()) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

// Integers written as table keys ("0x40 = ..." or "7 = ...").
std::optional<std::int64_t> parse_int_key(std::string_view s) {
  int base = 10;
  bool negative = false;
  if (!s.empty() && s.front() == '-') {
    negative = true;
    s.remove_prefix(1);
  }
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
    base = 16;
    s.remove_prefix(2);
  }
  if (s.empty() || s.size() > 12) return std::nullopt;
  std::int64_t v = 0;
  for (const char c : s) {
    const int d = hex_digit_value(c);
    if (d < 0 || d >= base) return std::nullopt;
    v = v * base + d;
  }
  return negative ? -v : v;
}

std::string hex_addr(std::uint32_t a) {
  return fmt::format("0x{:04X}", a);
}

// The space kind a function code implies, if a map may list it. FC22 and FC23 address
// holding registers too, but maps do not list them: device decoding delivers either what a
// transaction read or what it wrote, and FC23 does both.
std::optional<SpaceKind> kind_of_function(std::int64_t fc) {
  if (fc < 0 || fc > 0xFF || fc == fc::kMaskWriteRegister ||
      fc == fc::kReadWriteMultipleRegisters) {
    return std::nullopt;
  }
  const auto table = data_table_of(static_cast<std::uint8_t>(fc));
  if (!table) return std::nullopt;
  return is_bit_table(*table) ? SpaceKind::kBits : SpaceKind::kRegisters;
}

class Loader {
 public:
  explicit Loader(std::string_view file) : file_(file) {}

  MapLoadResult run(std::string_view text) {
    toml::table root;
    try {
      root = toml::parse(text, file_);
    } catch (const toml::parse_error& e) {
      error(e.source().begin.line, std::string(e.description()));
      return finish();
    }
    check_keys(root, kTopKeys, "the top level", 1);
    if (const auto* device = root.get("device"); device == nullptr) {
      error(1, "missing table [device]");
    } else if (const auto* t = table_or_error(*device, "[device]")) {
      read_device(*t);
    }
    // Vars first: points refer to them.
    if (const auto* vars = root.get("var")) {
      if (const auto* t = table_or_error(*vars, "[var]")) read_vars(*t);
    }
    if (const auto* ex = root.get("exceptions")) {
      if (const auto* t = table_or_error(*ex, "[exceptions]")) read_exceptions(*t);
    }
    if (const auto* spaces = root.get("space"); spaces == nullptr) {
      error(1, "missing [space.<id>] tables: a map needs at least one address space");
    } else if (const auto* t = table_or_error(*spaces, "[space]")) {
      // In file order (toml++ iterates keys sorted), so that a clash is reported at the
      // later definition.
      std::vector<std::pair<std::string, const toml::table*>> ordered;
      for (auto&& [key, node] : *t) {
        if (const auto* st = table_or_error(node, fmt::format("[space.{}]", key.str()))) {
          ordered.emplace_back(std::string(key.str()), st);
        }
      }
      std::stable_sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) {
        return a.second->source().begin.line < b.second->source().begin.line;
      });
      for (const auto& [id, st] : ordered) read_space(id, *st);
    }
    check_vars_learned();
    map_.index_spaces();
    return finish();
  }

 private:
  void error(std::uint32_t line, std::string message) {
    errors_.push_back({line, fmt::format("{}:{}: {}", file_, line, message)});
  }
  void error(const toml::node& at, std::string message) {
    error(at.source().begin.line, std::move(message));
  }

  MapLoadResult finish() {
    std::stable_sort(errors_.begin(), errors_.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    MapLoadResult result;
    for (auto& [line, text] : errors_) result.errors.push_back(std::move(text));
    result.map = std::move(map_);
    result.map.source_file = file_;
    return result;
  }

  const toml::table* table_or_error(const toml::node& node, const std::string& what) {
    if (const auto* t = node.as_table()) return t;
    error(node, fmt::format("{} must be a table", what));
    return nullptr;
  }

  void check_keys(const toml::table& t, Keys allowed, std::string_view where,
                  std::uint32_t fallback_line = 0) {
    for (auto&& [key, node] : t) {
      if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
      std::uint32_t line = key.source().begin.line;
      if (line == 0) line = node.source().begin.line;
      if (line == 0) line = fallback_line;
      error(line,
            fmt::format("unknown key '{}' in {} (allowed: {})", key.str(), where, join(allowed)));
    }
  }

  std::optional<std::string> get_string(const toml::table& t, std::string_view key,
                                        std::string_view where, bool required) {
    const auto* node = t.get(key);
    if (node == nullptr) {
      if (required) error(t, fmt::format("{}: missing key '{}'", where, key));
      return std::nullopt;
    }
    if (const auto* s = node->as_string()) return s->get();
    error(*node, fmt::format("{}: '{}' must be a string", where, key));
    return std::nullopt;
  }

  std::optional<std::int64_t> get_int(const toml::table& t, std::string_view key,
                                      std::string_view where, std::int64_t lo, std::int64_t hi,
                                      bool required) {
    const auto* node = t.get(key);
    if (node == nullptr) {
      if (required) error(t, fmt::format("{}: missing key '{}'", where, key));
      return std::nullopt;
    }
    const auto* i = node->as_integer();
    if (i == nullptr) {
      error(*node, fmt::format("{}: '{}' must be an integer", where, key));
      return std::nullopt;
    }
    const std::int64_t v = i->get();
    if (v < lo || v > hi) {
      error(*node, fmt::format("{}: '{}' = {} is outside {}..{}", where, key, v, lo, hi));
      return std::nullopt;
    }
    return v;
  }

  std::optional<double> number_of(const toml::node& node) {
    if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
    if (const auto* f = node.as_floating_point()) {
      if (std::isfinite(f->get())) return f->get();
    }
    return std::nullopt;
  }

  std::optional<double> get_number(const toml::table& t, std::string_view key,
                                   std::string_view where) {
    const auto* node = t.get(key);
    if (node == nullptr) return std::nullopt;
    auto v = number_of(*node);
    if (!v) error(*node, fmt::format("{}: '{}' must be a finite number", where, key));
    return v;
  }

  std::optional<WordOrder> get_word_order(const toml::table& t, std::string_view where) {
    const auto s = get_string(t, "word_order", where, false);
    if (!s) return std::nullopt;
    if (*s == "hi_lo") return WordOrder::kHighFirst;
    if (*s == "lo_hi") return WordOrder::kLowFirst;
    error(*t.get("word_order"),
          fmt::format("{}: word_order '{}' is not one of: hi_lo, lo_hi", where, *s));
    return std::nullopt;
  }

  void read_device(const toml::table& t) {
    check_keys(t, kDeviceKeys, "[device]", t.source().begin.line);
    if (auto model = get_string(t, "model", "[device]", true)) {
      if (!is_model_key(*model)) {
        error(*t.get("model"), fmt::format("[device]: model '{}' must be lowercase letters, "
                                           "digits, '_' or '-'",
                                           *model));
      }
      map_.model = *model;
    }
    map_.name = get_string(t, "name", "[device]", true).value_or("");
    map_.vendor = get_string(t, "vendor", "[device]", false).value_or("");
    map_.manual = get_string(t, "manual", "[device]", false).value_or("");
    map_.doc = get_string(t, "doc", "[device]", false).value_or("");
    default_order_ = get_word_order(t, "[device]").value_or(WordOrder::kHighFirst);
  }

  void read_vars(const toml::table& t) {
    for (auto&& [key, node] : t) {
      const std::string where = fmt::format("[var.{}]", key.str());
      const auto* vt = table_or_error(node, where);
      if (vt == nullptr) continue;
      check_keys(*vt, kVarKeys, where, vt->source().begin.line);
      Var var;
      var.name = std::string(key.str());
      var.default_value = get_number(*vt, "default", where);
      var.doc = get_string(*vt, "doc", where, false).value_or("");
      var_lines_.push_back(vt->source().begin.line);
      var_learned_.push_back(false);
      map_.vars.push_back(std::move(var));
    }
  }

  std::optional<std::size_t> find_var(std::string_view name) const {
    for (std::size_t i = 0; i < map_.vars.size(); ++i) {
      if (map_.vars[i].name == name) return i;
    }
    return std::nullopt;
  }

  void check_vars_learned() {
    for (std::size_t i = 0; i < map_.vars.size(); ++i) {
      if (!var_learned_[i]) {
        error(var_lines_[i], fmt::format("[var.{0}] is never learned: no point has "
                                         "learn = \"{0}\"",
                                         map_.vars[i].name));
      }
    }
  }

  void read_exceptions(const toml::table& t) {
    for (auto&& [key, node] : t) {
      const auto code = parse_int_key(key.str());
      std::uint32_t line = key.source().begin.line;
      if (line == 0) line = node.source().begin.line;
      if (!code || *code < 1 || *code > 255) {
        error(line,
              fmt::format("[exceptions]: key '{}' is not an exception code 1..255", key.str()));
        continue;
      }
      const auto* s = node.as_string();
      if (s == nullptr || s->get().empty()) {
        error(line, fmt::format("[exceptions]: code {} must name a non-empty string", *code));
        continue;
      }
      map_.exceptions.push_back({static_cast<std::uint8_t>(*code), s->get()});
    }
  }

  void read_space(std::string id, const toml::table& t) {
    const std::string where = fmt::format("[space.{}]", id);
    check_keys(t, kSpaceKeys, where, t.source().begin.line);
    Space space;
    space.id = std::move(id);
    space.doc = get_string(t, "doc", where, false).value_or("");
    const auto* fns = t.get("functions");
    std::optional<SpaceKind> kind;
    if (fns == nullptr) {
      error(t, fmt::format("{}: missing key 'functions'", where));
    } else if (const auto* arr = fns->as_array(); arr == nullptr || arr->empty()) {
      error(*fns,
            fmt::format("{}: 'functions' must be a non-empty array of function codes", where));
    } else {
      for (const auto& f : *arr) {
        const auto* i = f.as_integer();
        const auto k = i != nullptr ? kind_of_function(i->get()) : std::nullopt;
        if (!k) {
          error(f, fmt::format("{}: functions: {} is not one of 1, 2, 3, 4, 5, 6, 15, 16", where,
                               i != nullptr ? std::to_string(i->get()) : "a non-integer"));
          continue;
        }
        if (kind && *kind != *k) {
          error(f, fmt::format("{}: functions mix bit (1, 2, 5, 15) and register (3, 4, 6, 16) "
                               "codes",
                               where));
          continue;
        }
        kind = k;
        const auto fc = static_cast<std::uint8_t>(i->get());
        if (map_.space_for(fc) != nullptr || space.serves(fc)) {
          error(f, fmt::format("{}: function {} already addresses another space", where, fc));
          continue;
        }
        space.functions.push_back(fc);
      }
    }
    space.kind = kind.value_or(SpaceKind::kRegisters);
    if (const auto a = get_string(t, "addressing", where, false)) {
      if (*a == "byte") {
        space.addressing = Addressing::kByte;
        if (space.kind == SpaceKind::kBits) {
          error(*t.get("addressing"), fmt::format("{}: byte addressing applies to register "
                                                  "spaces only",
                                                  where));
        }
      } else if (*a != "word") {
        error(*t.get("addressing"),
              fmt::format("{}: addressing '{}' is not one of: word, byte", where, *a));
      }
    }
    if (const auto* pts = t.get("point")) {
      if (const auto* arr = pts->as_array()) {
        for (const auto& p : *arr) {
          if (const auto* pt = p.as_table()) {
            read_point(space, *pt);
          } else {
            error(p, fmt::format("{}: each point must be a table", where));
          }
        }
      } else {
        error(*pts, fmt::format("{}: 'point' must be an array of tables ([[space.{}.point]])",
                                where, space.id));
      }
    }
    check_overlaps(space);
    space.index_points();
    map_.spaces.push_back(std::move(space));
  }

  void read_point(Space& space, const toml::table& t) {
    Point p;
    p.line = t.source().begin.line;
    std::string where = fmt::format("point in [space.{}]", space.id);
    if (auto name = get_string(t, "name", where, true)) {
      p.name = *name;
      if (p.name.empty()) error(t, fmt::format("{}: 'name' must not be empty", where));
      where = fmt::format("point '{}'", p.name);
    }
    check_keys(t, kPointKeys, where, p.line);
    const auto addr = get_int(t, "addr", where, 0, 0xFFFF, true);
    p.addr = static_cast<std::uint32_t>(addr.value_or(0));
    // A point without a usable address is still checked, but not added: it would only
    // cause misleading overlap messages.
    const bool placeable = addr.has_value();

    const bool bits_space = space.kind == SpaceKind::kBits;
    p.type = bits_space ? PointType::kBit : PointType::kU16;
    if (const auto type = get_string(t, "type", where, false)) {
      static constexpr std::pair<std::string_view, PointType> kTypes[] = {
          {"u8", PointType::kU8},   {"i8", PointType::kI8},   {"u16", PointType::kU16},
          {"i16", PointType::kI16}, {"u32", PointType::kU32}, {"i32", PointType::kI32},
          {"f32", PointType::kF32}, {"bit", PointType::kBit}};
      const auto* found = std::find_if(std::begin(kTypes), std::end(kTypes),
                                       [&](const auto& e) { return e.first == *type; });
      const auto* node = t.get("type");
      if (found == std::end(kTypes)) {
        error(*node, fmt::format("{}: type '{}' is not one of: u8, i8, u16, i16, u32, i32, f32, "
                                 "bit",
                                 where, *type));
      } else {
        p.type = found->second;
        if (bits_space != (p.type == PointType::kBit)) {
          error(*node, fmt::format("{}: type '{}' does not fit [space.{}], a {} space", where,
                                   *type, space.id, bits_space ? "bit" : "register"));
        } else if (p.value_bytes() == 1 && space.addressing != Addressing::kByte) {
          error(*node, fmt::format("{}: type '{}' needs a byte-addressed space "
                                   "(addressing = \"byte\")",
                                   where, *type));
        }
      }
    }
    const bool wide = p.value_bytes() == 4;
    p.word_order = default_order_;
    if (const auto order = get_word_order(t, where)) {
      if (!wide) {
        error(*t.get("word_order"),
              fmt::format("{}: word_order applies to 32-bit types only", where));
      }
      p.word_order = *order;
    }
    if (const auto access = get_string(t, "access", where, false)) {
      if (*access == "ro") {
        p.access = Access::kReadOnly;
      } else if (*access == "wo") {
        p.access = Access::kWriteOnly;
      } else if (*access != "rw") {
        error(*t.get("access"),
              fmt::format("{}: access '{}' is not one of: ro, rw, wo", where, *access));
      }
    }
    const bool numeric_key_present = t.contains("scale") || t.contains("offset") ||
                                     t.contains("unit") || t.contains("decimals") ||
                                     t.contains("scale_by") || t.contains("range");
    if (p.type == PointType::kBit && numeric_key_present) {
      error(t, fmt::format("{}: a bit point takes no scale, offset, unit, decimals, scale_by "
                           "or range",
                           where));
    }
    if (const auto scale = get_number(t, "scale", where)) {
      if (*scale == 0.0) {
        error(*t.get("scale"), fmt::format("{}: scale must not be 0", where));
      } else {
        p.scale = *scale;
      }
    }
    p.offset = get_number(t, "offset", where).value_or(0.0);
    p.unit = get_string(t, "unit", where, false).value_or("");
    p.decimals = default_decimals(p.scale, p.offset, p.type);
    if (const auto d = get_int(t, "decimals", where, 0, 9, false)) {
      p.decimals = static_cast<int>(*d);
    }
    read_var_refs(t, p, where);
    read_enum(t, p, where);
    read_bits(t, p, where);
    if (const auto* range = t.get("range")) {
      const auto* arr = range->as_array();
      std::optional<double> lo;
      std::optional<double> hi;
      if (arr != nullptr && arr->size() == 2) {
        lo = number_of(*arr->get(0));
        hi = number_of(*arr->get(1));
      }
      if (!lo || !hi || *lo > *hi) {
        error(*range, fmt::format("{}: range must be [min, max] with min <= max", where));
      } else {
        p.min = lo;
        p.max = hi;
      }
    }
    if (const auto spare = get_int(t, "spare", where, 0, 8, false)) {
      if (bits_space) {
        error(*t.get("spare"), fmt::format("{}: spare applies to register spaces only", where));
      }
      p.spare = static_cast<std::uint16_t>(*spare);
    }
    read_classes(t, p, where);
    p.doc = get_string(t, "doc", where, false).value_or("");
    if (space.addressing == Addressing::kByte && p.value_bytes() >= 2 && (p.addr % 2) != 0) {
      error(*t.get("addr"), fmt::format("{}: a {}-bit point in a byte-addressed space must "
                                        "start at an even address",
                                        where, p.value_bytes() * 8));
    }
    if (addr && p.addr + p.units(space.addressing) > 0x10000) {
      error(*t.get("addr"), fmt::format("{}: extends past address 0xFFFF", where));
    }
    for (const auto& other : space.points) {
      if (!p.name.empty() && other.name == p.name) {
        error(t, fmt::format("{}: name already used at line {} in [space.{}]", where, other.line,
                             space.id));
      }
    }
    if (placeable) space.points.push_back(std::move(p));
  }

  static int default_decimals(double scale, double offset, PointType type) {
    if (type == PointType::kF32) return 3;
    double finest = std::abs(scale);
    if (offset != 0.0) finest = std::min(finest, std::abs(offset - std::trunc(offset)) + 1.0);
    if (finest >= 1.0 && std::trunc(scale) == scale && std::trunc(offset) == offset) return 0;
    // Digits needed to show one raw step: 0.1 → 1, 0.00106813 → 3, 0.4 → 1.
    const double digits = std::ceil(-std::log10(finest) - 1e-9);
    return static_cast<int>(std::clamp(digits, 0.0, 9.0));
  }

  void read_var_refs(const toml::table& t, Point& p, std::string_view where) {
    if (const auto* sb = t.get("scale_by")) {
      const auto* arr = sb->as_array();
      if (arr == nullptr) {
        error(*sb, fmt::format("{}: scale_by must be an array of var names", where));
      } else {
        for (const auto& n : *arr) {
          const auto* s = n.as_string();
          if (s == nullptr) {
            error(n, fmt::format("{}: scale_by must be an array of var names", where));
            continue;
          }
          if (const auto v = find_var(s->get())) {
            p.scale_by.push_back(*v);
          } else {
            error(n, fmt::format("{}: scale_by refers to '{}', which no [var.{}] declares", where,
                                 s->get(), s->get()));
          }
        }
      }
    }
    if (const auto learn = get_string(t, "learn", where, false)) {
      if (const auto v = find_var(*learn)) {
        p.learn = *v;
        var_learned_[*v] = true;
        if (!p.scale_by.empty()) {
          error(*t.get("learn"), fmt::format("{}: a point that is learned cannot itself be "
                                             "scaled by a var",
                                             where));
        }
      } else {
        error(*t.get("learn"), fmt::format("{}: learn refers to '{}', which no [var.{}] "
                                           "declares",
                                           where, *learn, *learn));
      }
    }
  }

  // An empty class is kept: it says "none" where the unit would give one.
  void read_classes(const toml::table& t, Point& p, std::string_view where) {
    if (auto device_class = get_string(t, "device_class", where, false)) {
      if (!device_class->empty() && !is_device_class(*device_class)) {
        error(*t.get("device_class"),
              fmt::format("{}: device_class '{}' must be a Home Assistant sensor device class, "
                          "lowercase letters, digits and '_' (e.g. \"voltage\"), or \"\" for none",
                          where, *device_class));
      } else {
        p.device_class = std::move(device_class);
      }
    }
    if (auto state_class = get_string(t, "state_class", where, false)) {
      if (!state_class->empty() && !is_state_class(*state_class)) {
        error(*t.get("state_class"),
              fmt::format("{}: state_class '{}' is not one of: measurement, total, "
                          "total_increasing (or \"\" for none)",
                          where, *state_class));
      } else {
        p.state_class = std::move(state_class);
      }
    }
  }

  void read_enum(const toml::table& t, Point& p, std::string_view where) {
    const auto* node = t.get("enum");
    if (node == nullptr) return;
    const auto* et = node->as_table();
    if (et == nullptr) {
      error(*node, fmt::format("{}: enum must be a table of value = \"text\"", where));
      return;
    }
    if (p.type == PointType::kF32) {
      error(*node, fmt::format("{}: enum applies to integer and bit types only", where));
    }
    for (auto&& [key, val] : *et) {
      std::uint32_t line = key.source().begin.line;
      if (line == 0) line = val.source().begin.line;
      const auto v = parse_int_key(key.str());
      const auto* s = val.as_string();
      if (!v) {
        error(line, fmt::format("{}: enum key '{}' is not an integer", where, key.str()));
      } else if (s == nullptr) {
        error(line, fmt::format("{}: enum value for {} must be a string", where, *v));
      } else {
        p.enums.push_back({*v, s->get()});
      }
    }
  }

  void read_bits(const toml::table& t, Point& p, std::string_view where) {
    const auto* node = t.get("bits");
    if (node == nullptr) return;
    const auto* arr = node->as_array();
    if (arr == nullptr) {
      error(*node, fmt::format("{}: bits must be an array of tables {{bit, name}}", where));
      return;
    }
    const unsigned width_bits = p.value_bytes() * 8;
    if (p.type == PointType::kF32 || p.type == PointType::kBit) {
      error(*node, fmt::format("{}: bits apply to integer types only", where));
      return;
    }
    for (const auto& b : *arr) {
      const auto* bt = b.as_table();
      if (bt == nullptr) {
        error(b, fmt::format("{}: each bits entry must be a table {{bit, name}}", where));
        continue;
      }
      const std::string bw = fmt::format("{}: bits entry", where);
      check_keys(*bt, kBitKeys, bw, bt->source().begin.line);
      BitField f;
      const auto bit = get_int(*bt, "bit", bw, 0, static_cast<std::int64_t>(width_bits) - 1, true);
      const auto width = get_int(*bt, "width", bw, 1, 32, false).value_or(1);
      f.name = get_string(*bt, "name", bw, true).value_or("");
      f.doc = get_string(*bt, "doc", bw, false).value_or("");
      if (!bit) continue;
      if (*bit + width > width_bits) {
        error(*bt, fmt::format("{}: bits {}..{} do not fit a {}-bit value", bw, *bit,
                               *bit + width - 1, width_bits));
        continue;
      }
      f.bit = static_cast<std::uint8_t>(*bit);
      f.width = static_cast<std::uint8_t>(width);
      for (const auto& other : p.bits) {
        const bool disjoint = f.bit + f.width <= other.bit || other.bit + other.width <= f.bit;
        if (!disjoint) {
          error(*bt, fmt::format("{}: bit {} overlaps field '{}'", bw, f.bit, other.name));
        }
      }
      p.bits.push_back(std::move(f));
    }
  }

  void check_overlaps(Space& space) {
    std::stable_sort(space.points.begin(), space.points.end(),
                     [](const Point& a, const Point& b) { return a.addr < b.addr; });
    for (std::size_t i = 1; i < space.points.size(); ++i) {
      const Point& prev = space.points[i - 1];
      const Point& cur = space.points[i];
      const std::uint32_t prev_end = prev.addr + prev.units(space.addressing);
      if (cur.addr < prev_end) {
        error(
            std::max(cur.line, prev.line),
            fmt::format("point '{}' at {} overlaps point '{}' ({}..{}, line {})",
                        cur.line > prev.line ? cur.name : prev.name,
                        hex_addr(cur.line > prev.line ? cur.addr : prev.addr),
                        cur.line > prev.line ? prev.name : cur.name,
                        hex_addr(cur.line > prev.line ? prev.addr : cur.addr),
                        hex_addr(cur.line > prev.line ? prev_end - 1
                                                      : cur.addr + cur.units(space.addressing) - 1),
                        std::min(cur.line, prev.line)));
      }
    }
  }

  std::string file_;
  DeviceMap map_;
  WordOrder default_order_ = WordOrder::kHighFirst;
  std::vector<std::uint32_t> var_lines_;
  std::vector<bool> var_learned_;
  std::vector<std::pair<std::uint32_t, std::string>> errors_;
};

std::string read_file(const std::string& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  if (!ok) return {};
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

MapLoadResult load_map_text(std::string_view text, std::string_view file_name) {
  return Loader(file_name).run(text);
}

MapLoadResult load_map_file(const std::string& path) {
  bool ok = false;
  const std::string text = read_file(path, ok);
  if (!ok) {
    MapLoadResult r;
    r.errors.push_back(fmt::format("{}: cannot read the file", path));
    return r;
  }
  auto result = load_map_text(text, path);
  // The model key is how users name the map (--device 1=yw2050): keep it equal to the
  // file name so that a map is found where its name says.
  const auto slash = path.find_last_of('/');
  std::string stem = path.substr(slash == std::string::npos ? 0 : slash + 1);
  if (stem.size() > 5 && stem.ends_with(".toml")) stem.resize(stem.size() - 5);
  if (result.errors.empty() && result.map.model != stem) {
    result.errors.push_back(
        fmt::format("{}:1: [device] model '{}' differs from the file name "
                    "'{}.toml'",
                    path, result.map.model, stem));
  }
  return result;
}

namespace {

// [live] of a bus file: strings, a port or a list of one or two ports, and `keep`.
template <typename Fail>
void read_live_section(const toml::table& t, LiveConfig& live, Fail& fail) {
  const std::pair<std::string_view, std::string*> texts[] = {
      {"bus_name", &live.bus_name}, {"write", &live.write},
      {"rotate", &live.rotate},     {"metrics", &live.metrics},
      {"events", &live.events},     {"summary_every", &live.summary_every},
      {"report", &live.report}};
  for (auto&& [k, v] : t) {
    bool known = false;
    for (const auto& [name, target] : texts) {
      if (k.str() != name) continue;
      known = true;
      const auto* s = v.as_string();
      if (s == nullptr || s->get().empty()) {
        fail(v, fmt::format("[live] {} must be a non-empty string", name));
      }
      *target = s->get();
    }
    if (known) continue;
    if (k.str() == "port") {
      // An empty path would only fail later, as "no such serial port ''".
      if (const auto* s = v.as_string()) {
        if (s->get().empty()) fail(v, "[live] port must be a path, e.g. \"/dev/ttyUSB0\"");
        live.ports = {s->get()};
      } else if (const auto* a = v.as_array(); a != nullptr && !a->empty() && a->size() <= 2) {
        live.ports.clear();
        for (auto&& p : *a) {
          if (!p.is_string() || p.as_string()->get().empty()) {
            fail(p, "[live] port must be a path or a list of one or two");
          }
          live.ports.push_back(p.as_string()->get());
        }
      } else {
        fail(v, "[live] port must be a path or a list of one or two");
      }
    } else if (k.str() == "keep") {
      const auto* i = v.as_integer();
      if (i == nullptr || i->get() < 0 || i->get() > 1000000) {
        fail(v, "[live] keep must be an integer 0..1000000");
      }
      live.keep = static_cast<std::size_t>(i->get());
    } else {
      fail(v, fmt::format("unknown key '{}' in [live] (allowed: port, bus_name, write, rotate, "
                          "keep, metrics, events, summary_every, report)",
                          k.str()));
    }
  }
}

}  // namespace

BusConfig load_bus_text(std::string_view text, std::string_view file_name) {
  const std::string file(file_name);
  toml::table root;
  try {
    root = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}: {}", file, e.source().begin.line, e.description()));
  }
  auto fail = [&](const toml::node& at, const std::string& what) {
    throw InputError(fmt::format("{}:{}: {}", file, at.source().begin.line, what));
  };
  BusConfig bus;
  for (auto&& [key, node] : root) {
    if (key.str() == "line") {
      const auto* t = node.as_table();
      if (t == nullptr) fail(node, "[line] must be a table");
      for (auto&& [k, v] : *t) {
        if (k.str() == "baud") {
          const auto* i = v.as_integer();
          if (i == nullptr || i->get() < 50 || i->get() > 4000000) {
            fail(v, "[line] baud must be an integer 50..4000000");
          }
          bus.baud = static_cast<std::uint32_t>(i->get());
        } else if (k.str() == "parity") {
          const auto* s = v.as_string();
          const auto p = s != nullptr ? parse_parity(s->get()) : std::nullopt;
          if (!p) fail(v, "[line] parity must be \"N\", \"E\" or \"O\"");
          bus.parity = p;
        } else if (k.str() == "stop") {
          const auto* i = v.as_integer();
          if (i == nullptr || (i->get() != 1 && i->get() != 2))
            fail(v, "[line] stop must be 1 or 2");
          bus.stop_bits = static_cast<std::uint8_t>(i->get());
        } else if (k.str() == "timeout_ms") {
          const auto* i = v.as_integer();
          if (i == nullptr || i->get() < 1 || i->get() > 600000) {
            fail(v, "[line] timeout_ms must be an integer 1..600000");
          }
          bus.timeout_ms = static_cast<std::uint32_t>(i->get());
        } else {
          fail(v, fmt::format("unknown key '{}' in [line] (allowed: baud, parity, stop, "
                              "timeout_ms)",
                              k.str()));
        }
      }
    } else if (key.str() == "slaves") {
      const auto* t = node.as_table();
      if (t == nullptr) fail(node, "[slaves] must be a table of address = \"model\"");
      for (auto&& [k, v] : *t) {
        const auto addr = parse_int_key(k.str());
        if (!addr || *addr < 1 || *addr > 247) {
          fail(v, fmt::format("[slaves]: '{}' is not a slave address 1..247", k.str()));
        }
        const auto* s = v.as_string();
        if (s == nullptr || !is_model_key(s->get())) {
          fail(v, fmt::format("[slaves]: slave {} must name a model such as \"yw2050\"", *addr));
        }
        // "2" and "02" are different TOML keys but one slave: which model wins is no choice
        // to make silently.
        for (const auto& known : bus.slaves) {
          if (known.slave == *addr)
            fail(v, fmt::format("[slaves]: slave {} is given twice", *addr));
        }
        bus.slaves.push_back({static_cast<std::uint8_t>(*addr), s->get(),
                              fmt::format("{}:{}", file, v.source().begin.line)});
      }
    } else if (key.str() == "live") {
      const auto* t = node.as_table();
      if (t == nullptr) fail(node, "[live] must be a table");
      read_live_section(*t, bus.live, fail);
    } else {
      fail(node, fmt::format("unknown key '{}' at the top level (allowed: line, slaves, live)",
                             key.str()));
    }
  }
  return bus;
}

BusConfig load_bus_file(const std::string& path) {
  bool ok = false;
  const std::string text = read_file(path, ok);
  if (!ok) throw InputError(fmt::format("{}: cannot read the bus file", path));
  return load_bus_text(text, path);
}

}  // namespace rtu::dissect
