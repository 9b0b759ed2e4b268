#include "dissect/point_format.hpp"

#include <iterator>
#include <string>

namespace rtu::dissect {
namespace {

template <typename... Args>
void put(fmt::memory_buffer& out, fmt::format_string<Args...> f, Args&&... args) {
  fmt::format_to(std::back_inserter(out), f, std::forward<Args>(args)...);
}

void put_hex(fmt::memory_buffer& out, std::uint64_t raw, unsigned bytes) {
  put(out, "0x{:0{}X}", raw, bytes * 2);
}

// "dir|jog|speed=3": set one-bit fields by name, wider fields as name=value, set bits
// without a field as bitN.
void put_bits_text(fmt::memory_buffer& out, const Point& p, std::uint64_t raw) {
  std::uint64_t described = 0;
  bool first = true;
  auto sep = [&] {
    if (!first) out.push_back('|');
    first = false;
  };
  for (const auto& f : p.bits) {
    const std::uint64_t mask = ((std::uint64_t{1} << f.width) - 1U) << f.bit;
    described |= mask;
    const std::uint64_t v = (raw & mask) >> f.bit;
    if (f.width == 1) {
      if (v != 0) {
        sep();
        out.append(std::string_view(f.name));
      }
    } else {
      sep();
      put(out, "{}={}", f.name, v);
    }
  }
  for (unsigned b = 0; b < p.value_bytes() * 8; ++b) {
    if ((raw >> b & 1U) != 0 && (described >> b & 1U) == 0) {
      sep();
      put(out, "bit{}", b);
    }
  }
}

std::string var_names(const Decoded& d, std::uint32_t mask) {
  std::string s;
  for (std::size_t i = 0; i < d.map->vars.size(); ++i) {
    if ((mask >> i & 1U) == 0) continue;
    if (!s.empty()) s += ',';
    s += d.map->vars[i].name;
  }
  return s;
}

void put_name(fmt::memory_buffer& out, const DecodedPoint& pt) {
  if (pt.point == nullptr) {
    put(out, "[0x{:04X}]", pt.addr);
  } else if (pt.spare_index > 0) {
    put(out, "{}+{}", pt.point->name, pt.spare_index);
  } else {
    out.append(std::string_view(pt.point->name));
  }
}

}  // namespace

void append_points_text(fmt::memory_buffer& out, const Decoded& d) {
  for (const auto& pt : d.points) {
    out.append(std::string_view("  "));
    put_name(out, pt);
    out.push_back('=');
    const Point* p = pt.point;
    if (p == nullptr || pt.spare_index > 0 || pt.partial) {
      if (pt.point != nullptr && pt.point->type == PointType::kBit) {
        put(out, "{}", pt.raw);
      } else {
        put_hex(out, pt.raw, pt.raw_bytes);
      }
      if (pt.partial) out.append(std::string_view("(part)"));
      continue;
    }
    if (p->type == PointType::kBit) {
      const auto* e = find_enum(*p, static_cast<std::int64_t>(pt.raw));
      if (e != nullptr) {
        out.append(std::string_view(e->text));
      } else {
        put(out, "{}", pt.raw);
      }
      continue;
    }
    if (!p->enums.empty()) {
      const auto* e = find_enum(*p, raw_as_integer(*p, pt.raw));
      if (e != nullptr) {
        out.append(std::string_view(e->text));
      } else {
        put(out, "{}(?)", raw_as_integer(*p, pt.raw));
      }
      continue;
    }
    if (!p->bits.empty()) {
      put_hex(out, pt.raw, pt.raw_bytes);
      const std::size_t mark = out.size();
      out.push_back('[');
      put_bits_text(out, *p, pt.raw);
      if (out.size() == mark + 1) {
        out.resize(mark);  // no bit set: the hex says it all
      } else {
        out.push_back(']');
      }
      continue;
    }
    if (pt.unknown_vars != 0) {
      put(out, "raw {} ({}?)", raw_as_integer(*p, pt.raw), var_names(d, pt.unknown_vars));
      continue;
    }
    put(out, "{:.{}f}", pt.value, p->decimals);
    if (!p->unit.empty()) put(out, " {}", p->unit);
    if (pt.assumed_vars != 0) {
      out.append(std::string_view(" ("));
      bool first = true;
      for (std::size_t i = 0; i < d.map->vars.size(); ++i) {
        if ((pt.assumed_vars >> i & 1U) == 0) continue;
        if (!first) out.push_back(',');
        first = false;
        put(out, "{}={}?", d.map->vars[i].name, *d.map->vars[i].default_value);
      }
      out.push_back(')');
    }
  }
}

void write_points_json(JsonWriter& json, const Decoded& d) {
  json.key("registers");
  json.begin_array();
  for (const auto& pt : d.points) {
    json.begin_object();
    json.field("addr", pt.addr);
    json.key("name");
    if (pt.point == nullptr) {
      json.null();
    } else if (pt.spare_index > 0) {
      json.value(fmt::format("{}+{}", pt.point->name, pt.spare_index));
    } else {
      json.value(std::string_view(pt.point->name));
    }
    json.field("raw", pt.raw);
    json.key("value");
    const Point* p = pt.point;
    const bool plain = p != nullptr && pt.spare_index == 0 && !pt.partial;
    if (plain && pt.has_value && pt.unknown_vars == 0) {
      json.value_fixed(pt.value, p->type == PointType::kBit ? 0 : p->decimals);
    } else {
      json.null();
    }
    json.key("unit");
    if (plain && !p->unit.empty()) {
      json.value(std::string_view(p->unit));
    } else {
      json.null();
    }
    if (plain && !p->enums.empty()) {
      const auto* e = find_enum(*p, raw_as_integer(*p, pt.raw));
      json.key("enum");
      if (e != nullptr) {
        json.value(std::string_view(e->text));
      } else {
        json.null();
      }
    }
    if (plain && !p->bits.empty()) {
      fmt::memory_buffer text;
      put_bits_text(text, *p, pt.raw);
      json.field("bits", std::string_view(text.data(), text.size()));
    }
    if (pt.partial) json.field("partial", true);
    if (pt.assumed_vars != 0) json.field("assumed", var_names(d, pt.assumed_vars));
    if (pt.unknown_vars != 0) json.field("unknown", var_names(d, pt.unknown_vars));
    json.end_object();
  }
  json.end_array();
}

}  // namespace rtu::dissect
