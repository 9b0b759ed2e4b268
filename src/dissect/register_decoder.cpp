#include "dissect/register_decoder.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <span>

namespace rtu::dissect {
namespace {

using Bytes = std::span<const std::uint8_t>;

std::uint16_t be16(Bytes b, std::size_t at) {
  return static_cast<std::uint16_t>((b[at] << 8U) | b[at + 1]);
}

struct BlockContext {
  const DeviceMap& map;
  const Space& space;
  RegisterPlans& plans;
  SlaveState& state;
  Decoded& out;
  bool write;           // the data is being written (access and learning rules)
  bool flag_undefined;  // add undefined_register for addresses the map lacks
};

// The bytes as one number, first byte highest.
std::uint64_t big_endian(Bytes bytes) {
  std::uint64_t raw = 0;
  for (const auto b : bytes) raw = (raw << 8U) | b;
  return raw;
}

std::uint64_t assemble(const Point& p, Bytes value) {
  if (p.value_bytes() == 4 && p.word_order == WordOrder::kLowFirst) {
    // Low word first (YW2050 energy, PT, CT): the second register is the high word.
    return (std::uint64_t{be16(value, 2)} << 16U) | be16(value, 0);
  }
  return big_endian(value);
}

double raw_number(const Point& p, std::uint64_t raw) {
  if (p.type == PointType::kF32) {
    return static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(raw)));
  }
  return static_cast<double>(raw_as_integer(p, raw));
}

void finish_value(BlockContext& c, DecodedPoint& d) {
  const Point& p = *d.point;
  d.base = raw_number(p, d.raw) * p.scale + p.offset;
  d.value = d.base;  // apply_scale_by() multiplies in the map's variables, where it has any
  d.has_value = true;
  if ((p.min && d.base < *p.min) || (p.max && d.base > *p.max))
    c.out.issues.add(IssueId::kOutOfRange);
  if (c.write && p.access == Access::kReadOnly) c.out.issues.add(IssueId::kReadOnlyWrite);
}

// Decodes register data `data` that starts at address `start` of the space, along the split
// of that range into the map's points (register_plans.hpp).
void decode_registers(BlockContext& c, std::uint32_t start, Bytes data) {
  const std::span<const RegisterStep> steps = c.plans.of(c.space, start, data.size());
  // Every step gives one point, made in place: not built aside and copied in.
  const std::size_t first = c.out.points.size();
  c.out.points.resize(first + steps.size());
  DecodedPoint* d = c.out.points.data() + first;
  for (const RegisterStep& s : steps) {
    const Bytes bytes = data.subspan(s.offset, s.length);
    d->addr = s.addr;
    d->point = s.point;
    d->raw_bytes = s.length;
    switch (s.kind) {
      case RegisterStep::Kind::kValue:
        d->raw = assemble(*s.point, bytes);
        finish_value(c, *d);
        break;
      case RegisterStep::Kind::kPartial:
        d->partial = true;
        d->raw = big_endian(bytes);
        c.out.issues.add(IssueId::kPartialPoint);
        if (c.write && s.point->access == Access::kReadOnly) {
          c.out.issues.add(IssueId::kReadOnlyWrite);
        }
        break;
      case RegisterStep::Kind::kSpare:
        // Shown raw, flagged when not zero.
        d->spare_index = s.spare_index;
        d->partial = s.length < 2;
        d->raw = big_endian(bytes);
        if (d->raw != 0) c.out.issues.add(IssueId::kReservedNonzero);
        break;
      case RegisterStep::Kind::kUndefined:
        d->raw = big_endian(bytes);
        if (c.flag_undefined) c.out.issues.add(IssueId::kUndefinedRegister);
        break;
    }
    ++d;
  }
}

// Decodes bits (coils or discrete inputs) starting at `start`.
void decode_bits(BlockContext& c, std::uint32_t start, BitView bits) {
  for (std::size_t k = 0; k < bits.size(); ++k) {
    DecodedPoint& d = c.out.points.emplace_back();
    d.addr = start + static_cast<std::uint32_t>(k);
    d.raw = bits[k] ? 1U : 0U;
    d.point = c.space.point_at(d.addr);
    if (d.point == nullptr) {
      if (c.flag_undefined) c.out.issues.add(IssueId::kUndefinedRegister);
    } else {
      d.base = static_cast<double>(d.raw);
      d.value = d.base;
      d.has_value = true;
      if (c.write && d.point->access == Access::kReadOnly) {
        c.out.issues.add(IssueId::kReadOnlyWrite);
      }
    }
  }
}

// Decodes the values a block carries, as far as its bytes go.
void decode_block(BlockContext& c, const DataBlock& b) {
  if (is_bit_table(b.table)) {
    decode_bits(c, b.addr, b.bits);
  } else {
    decode_registers(c, b.addr, b.words.bytes());
  }
}

void apply_learning(const Decoded& d, SlaveState& state) {
  // A point learns into one of the map's variables: a map without any has no point to look at.
  if (d.map->vars.empty()) return;
  for (const auto& pt : d.points) {
    if (pt.point != nullptr && pt.has_value && pt.point->learn) {
      state.vars[*pt.point->learn] = pt.base;
    }
  }
}

void apply_scale_by(Decoded& d, const SlaveState& state) {
  // A point scales by the map's variables: without any, every value is its base already.
  if (d.map->vars.empty()) return;
  for (auto& pt : d.points) {
    if (pt.point == nullptr || !pt.has_value) continue;
    pt.value = pt.base;
    for (const std::size_t v : pt.point->scale_by) {
      const auto bit = std::uint32_t{1} << v;
      if (state.vars[v]) {
        pt.value *= *state.vars[v];
      } else if (d.map->vars[v].default_value) {
        pt.value *= *d.map->vars[v].default_value;
        pt.assumed_vars |= bit;
        d.issues.add(IssueId::kScaleUnknown);
      } else {
        pt.unknown_vars |= bit;
        d.issues.add(IssueId::kScaleUnknown);
      }
    }
  }
}

// Decodes what a write block puts on the device into `c.out` (no learning).
void decode_write(BlockContext& c, const DataBlock& b) {
  // FC05 takes FF00 = on, 0000 = off (Modbus Application Protocol §6.5); anything else is
  // invalid and writes nothing.
  if (b.invalid_value) {
    c.out.issues.add(IssueId::kBadValue);
    return;
  }
  if (!b.count_fits) c.out.issues.add(IssueId::kByteCount);
  if (b.has_values) decode_block(c, b);
}

}  // namespace

std::int64_t raw_as_integer(const Point& point, std::uint64_t raw) {
  switch (point.type) {
    case PointType::kI8: return static_cast<std::int8_t>(raw & 0xFFU);
    case PointType::kI16: return static_cast<std::int16_t>(raw & 0xFFFFU);
    case PointType::kI32: return static_cast<std::int32_t>(raw & 0xFFFFFFFFU);
    default: return static_cast<std::int64_t>(raw);
  }
}

const EnumEntry* find_enum(const Point& point, std::int64_t value) {
  for (const auto& e : point.enums) {
    if (e.value == value) return &e;
  }
  return nullptr;
}

namespace {

// A request's writes are decoded; its reads are only checked against the map.
void decode_request(const DeviceMap& map, const Space& space, SlaveState& state,
                    const DataAccess& access, ReadRangeChecks& read_checks, RegisterPlans& plans,
                    Decoded& out) {
  for (const DataBlock& b : access) {
    if (b.write) {
      BlockContext c{map, space, plans, state, out, true, true};
      decode_write(c, b);
    } else {
      out.issues.merge(read_checks.of(space, b.addr, b.qty));
    }
  }
  apply_scale_by(out, state);
}

}  // namespace

void RegisterDecoder::decode(const DeviceMap& map, SlaveState& state, const Record& frame,
                             const DataAccess* request_access, Decoded& out) {
  out.clear();
  out.map = &map;
  if (state.vars.size() != map.vars.size()) state.reset(map);
  if (frame.kind != RecordKind::kFrame || !frame.crc_ok || frame.size < 4) return;
  if (frame.is_exception()) return;
  const std::uint8_t fc = frame.function();
  const Space* space = map.space_for(fc);

  if (frame.role == Role::kRequest) {
    if (space == nullptr) {
      out.issues.add(IssueId::kUnsupportedFunction);
      return;
    }
    out.space = space;
    if (request_access != nullptr) {
      decode_request(map, *space, state, *request_access, read_checks_, plans_, out);
    } else {
      decode_request(map, *space, state, data_access(frame, nullptr), read_checks_, plans_, out);
    }
    return;
  }

  if (frame.role != Role::kResponse || frame.request == nullptr || space == nullptr) return;
  const Record& req = *frame.request;
  if (req.function() != fc || !req.crc_ok) return;
  out.space = space;
  const DataAccess access = data_access(req, &frame);
  // The normal response confirms a write: learn what it set. Before any read, as the device
  // writes first (FC23).
  if (const DataBlock* w = access.write()) {
    BlockContext c{map, *space, plans_, state, scratch_, true, true};
    decode_write(c, *w);
    scratch_.map = &map;
    apply_learning(scratch_, state);
    apply_scale_by(scratch_, state);
    out.confirmed.assign(scratch_.points.begin(), scratch_.points.end());
    scratch_.clear();
  }
  if (const DataBlock* r = access.read(); r != nullptr && r->has_values) {
    // Undefined addresses were flagged on the request; here they are only shown.
    BlockContext c{map, *space, plans_, state, out, false, false};
    decode_block(c, *r);
    // Learn first, so that a read that brings PT and the voltages together scales them.
    apply_learning(out, state);
    apply_scale_by(out, state);
  }
}

}  // namespace rtu::dissect
