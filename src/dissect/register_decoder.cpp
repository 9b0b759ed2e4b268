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

// The few request fields a dissector needs, read straight from the ADU (address, function,
// fields..., CRC). Lengths are checked; a field that is not there is nullopt.
struct RequestFields {
  std::uint8_t function = 0;
  std::optional<std::uint16_t> addr;
  std::optional<std::uint16_t> quantity_or_value;  // FC01-04, 15, 16: quantity; FC05/06: value
  std::optional<std::uint8_t> byte_count;          // FC15, 16
  Bytes data;                                      // FC15, 16: what follows the byte count
};

RequestFields request_fields(const Record& r) {
  RequestFields f;
  const Bytes all = r.bytes();
  if (all.size() < 4) return f;
  const Bytes pdu = all.subspan(1, all.size() - 3);  // without address and CRC
  f.function = pdu[0];
  if (pdu.size() >= 3) f.addr = be16(pdu, 1);
  if (pdu.size() >= 5) f.quantity_or_value = be16(pdu, 3);
  if ((f.function == 15 || f.function == 16) && pdu.size() >= 6) {
    f.byte_count = pdu[5];
    f.data = pdu.subspan(6);
  }
  return f;
}

// Response data after the byte count of FC01-04, limited to what the frame holds.
Bytes response_data(const Record& r, bool& count_ok) {
  const Bytes all = r.bytes();
  count_ok = false;
  if (all.size() < 5) return {};
  const std::size_t count = all[2];
  const std::size_t available = all.size() - 5;  // address, function, count, CRC×2
  count_ok = count == available;
  return all.subspan(3, std::min(count, available));
}

bool is_read(std::uint8_t fc) {
  return fc >= 1 && fc <= 4;
}
bool is_write(std::uint8_t fc) {
  return fc == 5 || fc == 6 || fc == 15 || fc == 16;
}

struct BlockContext {
  const DeviceMap& map;
  const Space& space;
  SlaveState& state;
  Decoded& out;
  bool write;           // the data is being written (access and learning rules)
  bool flag_undefined;  // add undefined_register for addresses the map lacks
};

std::uint64_t assemble(const Point& p, Bytes value) {
  std::uint64_t raw = 0;
  if (p.value_bytes() == 4 && p.word_order == WordOrder::kLowFirst) {
    // Low word first (YW2050 energy, PT, CT): the second register is the high word.
    raw = (std::uint64_t{be16(value, 2)} << 16U) | be16(value, 0);
  } else {
    for (const auto b : value) raw = (raw << 8U) | b;
  }
  return raw;
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
  d.has_value = true;
  if ((p.min && d.base < *p.min) || (p.max && d.base > *p.max))
    c.out.issues.add(IssueId::kOutOfRange);
  if (c.write && p.access == Access::kReadOnly) c.out.issues.add(IssueId::kReadOnlyWrite);
}

// Decodes register data `data` that starts at address `start` of the space.
void decode_registers(BlockContext& c, std::uint32_t start, Bytes data) {
  const bool bytewise = c.space.addressing == Addressing::kByte;
  std::size_t off = 0;
  while (off < data.size()) {
    const std::uint32_t addr = bytewise ? start + static_cast<std::uint32_t>(off)
                                        : start + static_cast<std::uint32_t>(off / 2);
    const std::size_t left = data.size() - off;
    const Point* p = c.space.point_at(addr);
    DecodedPoint d;
    d.addr = addr;
    if (p == nullptr) {
      // An undefined register: one word, or in a byte space the bytes up to the next point
      // or register boundary.
      std::size_t len = 2;
      if (bytewise && ((addr % 2) != 0 || c.space.point_at(addr + 1) != nullptr)) len = 1;
      len = std::min(len, left);
      d.raw_bytes = static_cast<std::uint8_t>(len);
      for (std::size_t i = 0; i < len; ++i) d.raw = (d.raw << 8U) | data[off + i];
      if (c.flag_undefined) c.out.issues.add(IssueId::kUndefinedRegister);
      c.out.points.push_back(d);
      off += len;
      continue;
    }
    d.point = p;
    const std::uint32_t rel_units = addr - p->addr;
    const std::size_t rel_bytes = bytewise ? rel_units : std::size_t{rel_units} * 2;
    const std::size_t value_bytes = p->value_bytes();
    if (rel_bytes < value_bytes) {
      const std::size_t want = value_bytes - rel_bytes;
      if (rel_bytes == 0 && left >= want) {
        d.raw_bytes = static_cast<std::uint8_t>(value_bytes);
        d.raw = assemble(*p, data.subspan(off, value_bytes));
        finish_value(c, d);
      } else {
        // The transfer starts or ends inside the point: show the bytes, not a value.
        const std::size_t len = std::min(want, left);
        d.partial = true;
        d.raw_bytes = static_cast<std::uint8_t>(len);
        for (std::size_t i = 0; i < len; ++i) d.raw = (d.raw << 8U) | data[off + i];
        c.out.issues.add(IssueId::kPartialPoint);
        if (c.write && p->access == Access::kReadOnly) c.out.issues.add(IssueId::kReadOnlyWrite);
      }
      c.out.points.push_back(d);
      off += std::min(want, left);
      continue;
    }
    // A spare register travelling with the point: shown raw, flagged when not zero.
    const std::size_t spare_byte = rel_bytes - value_bytes;
    const std::size_t len = std::min<std::size_t>(2 - (spare_byte % 2), left);
    d.spare_index = static_cast<std::uint8_t>(spare_byte / 2 + 1);
    d.raw_bytes = static_cast<std::uint8_t>(len);
    for (std::size_t i = 0; i < len; ++i) d.raw = (d.raw << 8U) | data[off + i];
    d.partial = len < 2;
    if (d.raw != 0) c.out.issues.add(IssueId::kReservedNonzero);
    c.out.points.push_back(d);
    off += len;
  }
}

// Decodes `count` bits (coils or discrete inputs, LSB of the first byte first) at `start`.
void decode_bits(BlockContext& c, std::uint32_t start, std::size_t count, Bytes data) {
  count = std::min(count, data.size() * 8);
  for (std::size_t k = 0; k < count; ++k) {
    DecodedPoint d;
    d.addr = start + static_cast<std::uint32_t>(k);
    d.raw = (static_cast<unsigned>(data[k / 8]) >> (k % 8)) & 1U;
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
    c.out.points.push_back(d);
  }
}

// Checks a read request's range against the map: undefined addresses, and whether it
// starts or ends inside a point.
void check_read_range(BlockContext& c, std::uint32_t start, std::uint32_t quantity) {
  const bool bytewise = c.space.addressing == Addressing::kByte;
  const std::uint32_t units = bytewise ? quantity * 2 : quantity;
  const std::uint32_t end = start + units;
  std::uint32_t a = start;
  while (a < end) {
    const Point* p = c.space.point_at(a);
    if (p == nullptr) {
      c.out.issues.add(IssueId::kUndefinedRegister);
      const Point* next = c.space.point_from(a);
      if (next == nullptr) break;
      a = next->addr;
      continue;
    }
    const std::uint32_t value_end = p->addr + p->value_units(c.space.addressing);
    if ((a > p->addr && a < value_end) || (end > p->addr && end < value_end)) {
      c.out.issues.add(IssueId::kPartialPoint);
    }
    a = p->addr + p->units(c.space.addressing);
  }
}

void apply_learning(const Decoded& d, SlaveState& state) {
  for (const auto& pt : d.points) {
    if (pt.point != nullptr && pt.has_value && pt.point->learn) {
      state.vars[*pt.point->learn] = pt.base;
    }
  }
}

void apply_scale_by(Decoded& d, const SlaveState& state) {
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

// Decodes what a write request puts on the device into `out` (no learning).
void decode_write_request(const DeviceMap& map, const Space& space, SlaveState& state,
                          const Record& req, Decoded& out) {
  const RequestFields f = request_fields(req);
  if (!f.addr || !f.quantity_or_value) return;
  BlockContext c{map, space, state, out, true, true};
  const std::uint8_t value_bytes[2] = {static_cast<std::uint8_t>(*f.quantity_or_value >> 8U),
                                       static_cast<std::uint8_t>(*f.quantity_or_value & 0xFFU)};
  switch (f.function) {
    case 5: {
      // FF00 = on, 0000 = off (Modbus Application Protocol §6.5); anything else is invalid.
      const std::uint16_t v = *f.quantity_or_value;
      if (v != 0xFF00 && v != 0x0000) {
        out.issues.add(IssueId::kBadValue);
        return;
      }
      const std::uint8_t bit = v == 0xFF00 ? 1 : 0;
      decode_bits(c, *f.addr, 1, Bytes(&bit, 1));
      return;
    }
    case 6: decode_registers(c, *f.addr, Bytes(value_bytes, 2)); return;
    case 15:
    case 16: {
      if (!f.byte_count) return;
      const std::size_t quantity = *f.quantity_or_value;
      const std::size_t expected = f.function == 16 ? quantity * 2 : (quantity + 7) / 8;
      if (*f.byte_count != expected || *f.byte_count != f.data.size()) {
        out.issues.add(IssueId::kByteCount);
      }
      // As far as the frame's bytes go: never past the quantity, the count or the data.
      std::size_t n = std::min<std::size_t>({expected, *f.byte_count, f.data.size()});
      if (f.function == 16) {
        n -= n % 2;
        decode_registers(c, *f.addr, f.data.first(n));
      } else {
        decode_bits(c, *f.addr, quantity, f.data.first(n));
      }
      return;
    }
    default: return;
  }
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

void RegisterDecoder::decode(const DeviceMap& map, SlaveState& state, const Record& frame,
                             Decoded& out) {
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
    if (is_read(fc)) {
      const RequestFields f = request_fields(frame);
      if (f.addr && f.quantity_or_value) {
        BlockContext c{map, *space, state, out, false, true};
        check_read_range(c, *f.addr, *f.quantity_or_value);
      }
    } else if (is_write(fc)) {
      decode_write_request(map, *space, state, frame, out);
      apply_scale_by(out, state);
    }
    return;
  }

  if (frame.role != Role::kResponse || frame.request == nullptr || space == nullptr) return;
  const Record& req = *frame.request;
  if (req.function() != fc || !req.crc_ok) return;
  out.space = space;
  if (is_read(fc)) {
    const RequestFields f = request_fields(req);
    if (!f.addr || !f.quantity_or_value) return;
    bool count_ok = false;
    const Bytes data = response_data(frame, count_ok);
    // Undefined addresses were flagged on the request; here they are only shown.
    BlockContext c{map, *space, state, out, false, false};
    if (space->kind == SpaceKind::kBits) {
      decode_bits(c, *f.addr, *f.quantity_or_value, data);
    } else {
      decode_registers(c, *f.addr, data.first(data.size() - data.size() % 2));
    }
    // Learn first, so that a read that brings PT and the voltages together scales them.
    apply_learning(out, state);
    apply_scale_by(out, state);
  } else if (is_write(fc)) {
    // The normal response confirms the write: learn what it set.
    decode_write_request(map, *space, state, req, scratch_);
    scratch_.map = &map;
    apply_learning(scratch_, state);
    apply_scale_by(scratch_, state);
    out.confirmed.assign(scratch_.points.begin(), scratch_.points.end());
    scratch_.clear();
  }
}

}  // namespace rtu::dissect
