#include "capture/pcap_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <limits>
#include <system_error>

#include "capture/byte_order.hpp"
#include "capture/pcap_format.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

constexpr std::array<std::uint8_t, 4> kShbTypeBytes = {0x0A, 0x0D, 0x0D, 0x0A};
constexpr std::size_t kReadSize = 1024 * 1024;  // what one read from the file asks for

struct Interface {
  std::uint16_t link_type = 0;
  std::uint8_t tsresol = 6;  // absent if_tsresol means µs
  std::int64_t tsoffset = 0;
  Nanos step = 1000;
  // Decimal if_tsresol of at most 9 digits and no if_tsoffset (every capture rtuscope or
  // Wireshark writes): a timestamp is ticks × this many ns. 0: the general conversion.
  std::uint64_t ns_per_tick = 0;
  std::uint64_t offset = 0;  // of its IDB (or of the pcap header's link type)
  bool accepted = false;     // its link type is one the reader accepts (asked once, not per packet)
  std::string name;
  std::string description;
};

std::string link_type_list(const std::vector<std::uint16_t>& accepted) {
  std::string out;
  for (std::size_t i = 0; i < accepted.size(); ++i) {
    if (i > 0) out += i + 1 == accepted.size() ? " or " : ", ";
    out += std::to_string(accepted[i]);
  }
  return out;
}

Nanos step_of(std::uint8_t tsresol) {
  if ((tsresol & 0x80U) != 0) {
    const unsigned n = tsresol & 0x7FU;
    return n >= 30 ? 1 : std::max<Nanos>(1, kNanosPerSecond >> n);
  }
  Nanos step = kNanosPerSecond;
  for (unsigned i = 0; i < tsresol && step > 1; ++i) step /= 10;
  return step;
}

}  // namespace

std::optional<Nanos> pcapng_ticks_to_nanos(std::uint64_t ticks, std::uint8_t tsresol,
                                           std::int64_t offset_seconds) {
  std::int64_t nanos = 0;
  if ((tsresol & 0x80U) == 0) {
    const unsigned n = tsresol;
    if (n > 19) return std::nullopt;
    if (n <= 9) {
      std::uint64_t mul = 1;
      for (unsigned i = n; i < 9; ++i) mul *= 10;
      std::uint64_t product = 0;
      if (__builtin_mul_overflow(ticks, mul, &product)) return std::nullopt;
      if (product > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
        return std::nullopt;
      }
      nanos = static_cast<std::int64_t>(product);
    } else {
      std::uint64_t div = 1;
      for (unsigned i = 9; i < n; ++i) div *= 10;
      nanos = static_cast<std::int64_t>(ticks / div);
    }
  } else {
    unsigned n = tsresol & 0x7FU;
    if (n > 63) return std::nullopt;
    const std::uint64_t whole = ticks >> n;
    std::uint64_t fraction = ticks & ((std::uint64_t{1} << n) - 1);
    // fraction × 10^9 must fit in 64 bits: drop bits finer than 2^-34 s (0.06 ns) first.
    if (n > 34) {
      fraction >>= (n - 34);
      n = 34;
    }
    const std::uint64_t fraction_ns = (fraction * 1'000'000'000ULL) >> n;
    std::int64_t whole_ns = 0;
    if (whole > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) ||
        __builtin_mul_overflow(static_cast<std::int64_t>(whole), kNanosPerSecond, &whole_ns)) {
      return std::nullopt;
    }
    nanos = whole_ns + static_cast<std::int64_t>(fraction_ns);
  }
  std::int64_t offset_ns = 0;
  if (__builtin_mul_overflow(offset_seconds, kNanosPerSecond, &offset_ns) ||
      __builtin_add_overflow(nanos, offset_ns, &nanos)) {
    return std::nullopt;
  }
  return nanos;
}

bool is_pcap_file_start(std::span<const std::uint8_t> head) {
  if (head.size() < 4) return false;
  if (std::equal(kShbTypeBytes.begin(), kShbTypeBytes.end(), head.begin())) return true;
  for (const ByteOrder order : {ByteOrder::kLittle, ByteOrder::kBig}) {
    const std::uint32_t magic = load_u32(head, 0, order);
    if (magic == pcap::kMagicMicros || magic == pcap::kMagicNanos) return true;
  }
  return false;
}

struct PcapReader::Impl {
  std::vector<char> file_buffer;  // the file stream's buffer; declared first, freed last
  std::unique_ptr<std::istream> in;
  std::string name;
  std::vector<std::uint16_t> accepted;
  CaptureFileFormat format = CaptureFileFormat::kPcap;
  ByteOrder order = ByteOrder::kLittle;
  std::uint64_t offset = 0;  // bytes consumed so far
  std::uint64_t size = 0;    // of the file; 0 = unknown
  bool done = false;
  bool carry = false;  // block already holds the start of the next block

  // Classic pcap
  bool nanos = false;
  // pcapng
  std::int64_t section = -1;
  std::vector<Interface> interfaces;
  std::string first_accepted_description;
  bool accepted_seen = false;

  // The file is read in large pieces into `buffer`; a block is parsed where it lies there.
  // buffer[head, tail) holds bytes read from the file and not yet passed; the current block
  // (or record) is its first block.size() bytes, a view valid until the next block starts.
  std::vector<std::uint8_t> buffer;
  std::size_t head = 0;
  std::size_t tail = 0;
  std::span<const std::uint8_t> block;
  std::string comment;

  [[noreturn]] void fail(std::uint64_t at, std::string_view what) {
    done = true;
    throw InputError(fmt::format("{}: offset {}: {}", name, at, what));
  }

  // The next block starts after the current one.
  void start_block() {
    head += block.size();
    block = {buffer.data() + head, 0};
  }

  // Extends `block` by up to `n` bytes of the file; returns how many were available.
  std::size_t read_more(std::size_t n) {
    const std::size_t want = block.size() + n;
    if (tail - head < want) fill(want);
    const std::size_t got = std::min(n, tail - head - block.size());
    block = {buffer.data() + head, block.size() + got};
    offset += got;
    return got;
  }

  // Reads until buffer[head, tail) holds `want` bytes or the file ends. Large reads straight
  // from the stream's buffer: a call per block cost more than the parsing on captures of
  // millions of small blocks.
  void fill(std::size_t want) {
    if (buffer.size() - head < want) {
      std::copy(buffer.begin() + static_cast<std::ptrdiff_t>(head),
                buffer.begin() + static_cast<std::ptrdiff_t>(tail), buffer.begin());
      tail -= head;
      head = 0;
      if (buffer.size() < want) buffer.resize(std::max(want, kReadSize));
    }
    while (tail - head < want) {
      const auto got = static_cast<std::size_t>(
          in->rdbuf()->sgetn(reinterpret_cast<char*>(buffer.data() + tail),
                             static_cast<std::streamsize>(buffer.size() - tail)));
      if (got == 0) break;
      tail += got;
    }
  }

  bool accepts(std::uint16_t link_type) const {
    return accepted.empty() ||
           std::find(accepted.begin(), accepted.end(), link_type) != accepted.end();
  }

  // Every interface is added here, so that whether its link type is accepted is settled once
  // for all its packets.
  void add_interface(Interface iface) {
    iface.accepted = accepts(iface.link_type);
    if (iface.accepted && !accepted_seen) {
      accepted_seen = true;
      first_accepted_description = iface.description;
    }
    interfaces.push_back(std::move(iface));
  }

  void check_link_type(const Interface& iface, std::uint32_t id, std::uint64_t packet_at) {
    if (iface.accepted) return;
    if (format == CaptureFileFormat::kPcap) {
      fail(iface.offset, fmt::format("link type {} is not supported; expected {}", iface.link_type,
                                     link_type_list(accepted)));
    }
    fail(packet_at,
         fmt::format("packet on interface {} whose link type {} (declared by the interface "
                     "description block at offset {}) is not supported; expected {}",
                     id, iface.link_type, iface.offset, link_type_list(accepted)));
  }

  void open() {
    const std::size_t got = read_more(4);
    if (got < 4 || !is_pcap_file_start(block)) {
      fail(0,
           "not a pcap or pcapng file: expected the magic number A1B2C3D4, A1B23C4D or the "
           "pcapng section header 0A0D0D0A");
    }
    if (std::equal(kShbTypeBytes.begin(), kShbTypeBytes.end(), block.begin())) {
      format = CaptureFileFormat::kPcapng;
      carry = true;  // the 4 bytes read start the first block (works on pipes too)
      return;
    }
    format = CaptureFileFormat::kPcap;
    order = load_u32(block, 0, ByteOrder::kLittle) == pcap::kMagicMicros ||
                    load_u32(block, 0, ByteOrder::kLittle) == pcap::kMagicNanos
                ? ByteOrder::kLittle
                : ByteOrder::kBig;
    nanos = load_u32(block, 0, order) == pcap::kMagicNanos;
    if (read_more(pcap::kGlobalHeaderSize - 4) < pcap::kGlobalHeaderSize - 4) {
      fail(offset, fmt::format("pcap global header cut off after {} of {} bytes", offset,
                               pcap::kGlobalHeaderSize));
    }
    const std::uint16_t major = load_u16(block, 4, order);
    if (major != 2) {
      fail(4, fmt::format("pcap version {}.{} is not supported; expected 2.x", major,
                          load_u16(block, 6, order)));
    }
    Interface iface;
    iface.link_type = static_cast<std::uint16_t>(load_u32(block, 20, order) & 0xFFFFU);
    iface.step = nanos ? 1 : kNanosPerMicro;
    iface.offset = 20;
    add_interface(std::move(iface));
    section = 0;
  }

  bool next_pcap(CapturePacket& out) {
    const std::uint64_t at = offset;
    start_block();
    const std::size_t got = read_more(pcap::kRecordHeaderSize);
    if (got == 0) return false;
    if (got < pcap::kRecordHeaderSize) {
      fail(at, fmt::format("record header cut off after {} of {} bytes: the file ends", got,
                           pcap::kRecordHeaderSize));
    }
    const std::uint32_t seconds = load_u32(block, 0, order);
    const std::uint32_t fraction = load_u32(block, 4, order);
    const std::uint32_t captured = load_u32(block, 8, order);
    const std::uint32_t original = load_u32(block, 12, order);
    if (captured > pcap::kMaxRecordSize) {
      fail(at + 8, fmt::format("record length {} is implausible (limit {}); expected a record "
                               "header",
                               captured, pcap::kMaxRecordSize));
    }
    const std::size_t data_got = read_more(captured);
    if (data_got < captured) {
      fail(at, fmt::format("record of {} data bytes cut off after {}: the file ends", captured,
                           data_got));
    }
    const Interface& iface = interfaces.front();
    check_link_type(iface, 0, at);
    out = CapturePacket{};
    out.link_type = iface.link_type;
    out.t = static_cast<Nanos>(seconds) * kNanosPerSecond +
            static_cast<Nanos>(fraction) * (nanos ? 1 : kNanosPerMicro);
    out.resolution = iface.step;
    out.original_length = original;
    out.offset = at;
    out.data = std::span<const std::uint8_t>(block).subspan(pcap::kRecordHeaderSize);
    return true;
  }

  // Calls fn(code, value, value_offset_in_block) for each option in block[start, end).
  template <typename Fn>
  void for_each_option(std::uint64_t block_at, std::size_t start, std::size_t end, Fn&& fn) {
    std::size_t pos = start;
    while (pos < end) {
      if (end - pos < 4) {
        fail(block_at + pos, fmt::format("option header cut off: {} bytes left before the "
                                         "block's trailing length, expected 4",
                                         end - pos));
      }
      const std::uint16_t code = load_u16(block, pos, order);
      const std::uint16_t length = load_u16(block, pos + 2, order);
      if (code == pcap::kOptEndOfOpt) return;
      const std::size_t padded = (static_cast<std::size_t>(length) + 3U) & ~std::size_t{3};
      if (padded > end - pos - 4) {
        fail(block_at + pos,
             fmt::format("option {} of length {} runs past the end of its block", code, length));
      }
      fn(code, std::span<const std::uint8_t>(block).subspan(pos + 4, length), pos + 4);
      pos += 4 + padded;
    }
  }

  static std::string_view as_text(std::span<const std::uint8_t> value) {
    std::string_view text(reinterpret_cast<const char*>(value.data()), value.size());
    while (!text.empty() && text.back() == '\0') text.remove_suffix(1);
    return text;
  }

  void read_section_header(std::uint64_t at, std::uint32_t length) {
    const std::uint16_t major = load_u16(block, 12, order);
    if (major != 1) {
      fail(at + 12, fmt::format("pcapng version {}.{} is not supported; expected 1.x", major,
                                load_u16(block, 14, order)));
    }
    ++section;
    interfaces.clear();
    (void)length;
  }

  void read_interface(std::uint64_t at, std::uint32_t length) {
    Interface iface;
    iface.link_type = load_u16(block, 8, order);
    iface.offset = at;
    for_each_option(
        at, 16, length - 4,
        [&](std::uint16_t code, std::span<const std::uint8_t> value, std::size_t pos) {
          if (code == pcap::kIfTsResol) {
            if (value.size() != 1) {
              fail(at + pos, fmt::format("if_tsresol has length {}; expected 1", value.size()));
            }
            iface.tsresol = value[0];
            const unsigned n = value[0] & 0x7FU;
            if (((value[0] & 0x80U) == 0 && n > 19) || n > 63) {
              fail(at + pos, fmt::format("if_tsresol 0x{:02x} is out of range", value[0]));
            }
          } else if (code == pcap::kIfTsOffset) {
            if (value.size() != 8) {
              fail(at + pos, fmt::format("if_tsoffset has length {}; expected 8", value.size()));
            }
            iface.tsoffset = static_cast<std::int64_t>(load_u64(value, 0, order));
          } else if (code == pcap::kIfName) {
            iface.name = as_text(value);
          } else if (code == pcap::kIfDescription) {
            iface.description = as_text(value);
          }
        });
    iface.step = step_of(iface.tsresol);
    if ((iface.tsresol & 0x80U) == 0 && iface.tsresol <= 9 && iface.tsoffset == 0) {
      iface.ns_per_tick = static_cast<std::uint64_t>(iface.step);
    }
    add_interface(std::move(iface));
  }

  static_assert(sizeof(CapturePacket) == 120,
                "new CapturePacket field: set it in read_packet(), which sets each field");

  // EPB (type 6) and the obsolete Packet Block (type 2) share their layout except that
  // the latter splits the interface field into interface (u16) and drop count (u16).
  void read_packet(std::uint64_t at, std::uint32_t type, std::uint32_t length, CapturePacket& out) {
    const std::uint32_t id =
        type == pcap::kBlockEnhancedPacket ? load_u32(block, 8, order) : load_u16(block, 8, order);
    if (id >= interfaces.size()) {
      fail(at + 8, fmt::format("packet on interface {}, but section {} has {} interface "
                               "description block(s) before it",
                               id, section, interfaces.size()));
    }
    const Interface& iface = interfaces[id];
    check_link_type(iface, id, at);
    const std::uint64_t ticks =
        (std::uint64_t{load_u32(block, 12, order)} << 32U) | load_u32(block, 16, order);
    const std::uint32_t captured = load_u32(block, 20, order);
    const std::uint32_t original = load_u32(block, 24, order);
    const std::size_t room = length - 4 - 28;
    if (captured > room) {
      fail(at + 20, fmt::format("captured length {} runs past the end of the {}-byte block",
                                captured, length));
    }
    // The common case in line: a conversion that returns std::optional out of line makes
    // its caller reload the result from the stack in a width it was not stored in, a stall
    // on every packet.
    std::optional<Nanos> t;
    std::uint64_t ns = 0;
    if (iface.ns_per_tick != 0 && !__builtin_mul_overflow(ticks, iface.ns_per_tick, &ns) &&
        ns <= static_cast<std::uint64_t>(std::numeric_limits<Nanos>::max())) {
      t = static_cast<Nanos>(ns);
    } else {
      t = pcapng_ticks_to_nanos(ticks, iface.tsresol, iface.tsoffset);
    }
    if (!t) {
      fail(at + 12, fmt::format("timestamp {} with if_tsresol 0x{:02x} does not fit in 64-bit "
                                "nanoseconds",
                                ticks, iface.tsresol));
    }
    const std::size_t options_start = 28 + ((static_cast<std::size_t>(captured) + 3U) & ~3U);
    comment.clear();
    std::optional<std::uint32_t> flags;
    for_each_option(at, std::min<std::size_t>(options_start, length - 4), length - 4,
                    [&](std::uint16_t code, std::span<const std::uint8_t> value, std::size_t pos) {
                      if (code == pcap::kOptComment) {
                        if (!comment.empty()) comment += '\n';
                        comment += as_text(value);
                      } else if (code == pcap::kEpbFlags) {
                        if (value.size() != 4) {
                          fail(at + pos,
                               fmt::format("epb_flags has length {}; expected 4", value.size()));
                        }
                        flags = load_u32(value, 0, order);
                      }
                    });
    // Every field named, so none keeps the previous packet's value; no reset of the whole
    // struct before (a store per field more at every packet).
    out.link_type = iface.link_type;
    out.interface_id = id;
    out.section = static_cast<std::uint32_t>(section);
    out.t = *t;
    out.resolution = iface.step;
    out.original_length = original;
    out.flags = flags;
    out.offset = at;
    out.data = std::span<const std::uint8_t>(block).subspan(28, captured);
    out.comment = comment;
    out.interface_name = iface.name;
    out.interface_description = iface.description;
  }

  bool next_pcapng(CapturePacket& out) {
    for (;;) {
      std::uint64_t at = offset;
      std::size_t got = 0;
      if (carry) {
        carry = false;
        at = 0;
        got = block.size();
      } else {
        start_block();
      }
      got += read_more(8 - got);
      if (got == 0) {
        if (section < 0) fail(0, "empty file: expected a pcapng section header block");
        return false;
      }
      if (got < 8) {
        fail(at, fmt::format("block header cut off after {} of 8 bytes: the file ends", got));
      }
      const bool is_shb = std::equal(kShbTypeBytes.begin(), kShbTypeBytes.end(), block.begin());
      if (section < 0 && !is_shb) {
        fail(at, "expected a pcapng section header block (type 0A0D0D0A)");
      }
      if (is_shb) {
        if (read_more(4) < 4) fail(at + 8, "byte-order magic cut off: the file ends");
        if (load_u32(block, 8, ByteOrder::kLittle) == pcap::kByteOrderMagic) {
          order = ByteOrder::kLittle;
        } else if (load_u32(block, 8, ByteOrder::kBig) == pcap::kByteOrderMagic) {
          order = ByteOrder::kBig;
        } else {
          fail(at + 8, fmt::format("byte-order magic {:02x}{:02x}{:02x}{:02x} is not 1A2B3C4D "
                                   "in either byte order",
                                   block[8], block[9], block[10], block[11]));
        }
      }
      const std::uint32_t type = load_u32(block, 0, order);
      const std::uint32_t length = load_u32(block, 4, order);
      if (length < pcap::kBlockFramingSize) {
        fail(at + 4, fmt::format("block length {} is smaller than a block header and trailer "
                                 "({} bytes)",
                                 length, pcap::kBlockFramingSize));
      }
      if (length % 4 != 0) {
        fail(at + 4, fmt::format("block length {} is not a multiple of 4", length));
      }
      if (length > pcap::kMaxRecordSize) {
        fail(at + 4, fmt::format("block length {} is implausible (limit {})", length,
                                 pcap::kMaxRecordSize));
      }
      std::uint32_t minimum = pcap::kBlockFramingSize;
      std::string_view kind = "block";
      switch (type) {
        case pcap::kBlockSectionHeader:
          minimum = pcap::kMinSectionHeaderSize;
          kind = "section header block";
          break;
        case pcap::kBlockInterfaceDescription:
          minimum = pcap::kMinInterfaceDescriptionSize;
          kind = "interface description block";
          break;
        case pcap::kBlockEnhancedPacket:
          minimum = pcap::kMinEnhancedPacketSize;
          kind = "enhanced packet block";
          break;
        case pcap::kBlockObsoletePacket:
          minimum = pcap::kMinObsoletePacketSize;
          kind = "packet block";
          break;
        default: break;
      }
      if (length < minimum) {
        fail(at + 4, fmt::format("{} length {} is smaller than its fixed fields ({} bytes)", kind,
                                 length, minimum));
      }
      const std::size_t want = length - block.size();
      const std::size_t body = read_more(want);
      if (body < want) {
        fail(at, fmt::format("{} of {} bytes (type 0x{:08x}) cut off after {} bytes: the file "
                             "ends",
                             kind, length, type, block.size()));
      }
      const std::uint32_t trailer = load_u32(block, length - 4, order);
      if (trailer != length) {
        fail(at + length - 4, fmt::format("trailing block length {} differs from the leading "
                                          "length {} of the {} at offset {}",
                                          trailer, length, kind, at));
      }
      switch (type) {
        case pcap::kBlockSectionHeader: read_section_header(at, length); break;
        case pcap::kBlockInterfaceDescription: read_interface(at, length); break;
        case pcap::kBlockEnhancedPacket:
        case pcap::kBlockObsoletePacket: read_packet(at, type, length, out); return true;
        case pcap::kBlockSimplePacket:
          fail(at,
               "simple packet block: it carries no timestamp, which a serial capture "
               "needs; expected enhanced packet blocks");
        default: break;  // statistics, name resolution, custom blocks: not needed
      }
    }
  }
};

constexpr std::size_t kFileBufferSize = 256 * 1024;

PcapReader::PcapReader(const CaptureFile& input, std::vector<std::uint16_t> accepted_link_types)
    : impl_(std::make_unique<Impl>()) {
  auto file = std::make_unique<std::ifstream>();
  // A larger buffer than the default few KB: fewer read() calls on large captures.
  impl_->file_buffer.resize(kFileBufferSize);
  file->rdbuf()->pubsetbuf(impl_->file_buffer.data(),
                           static_cast<std::streamsize>(impl_->file_buffer.size()));
  file->open(input.path, std::ios::binary);
  if (!*file) throw InputError(fmt::format("{}: cannot open file", input.name));
  impl_->in = std::move(file);
  impl_->name = input.name;
  std::error_code error;
  const auto size = std::filesystem::file_size(input.path, error);
  if (!error) impl_->size = size;
  impl_->accepted = std::move(accepted_link_types);
  impl_->open();
}

PcapReader::PcapReader(std::unique_ptr<std::istream> in, std::string name,
                       std::vector<std::uint16_t> accepted_link_types)
    : impl_(std::make_unique<Impl>()) {
  impl_->in = std::move(in);
  impl_->name = std::move(name);
  impl_->accepted = std::move(accepted_link_types);
  impl_->open();
}

PcapReader::~PcapReader() = default;

bool PcapReader::next(CapturePacket& out) {
  if (impl_->done) return false;
  const bool more =
      impl_->format == CaptureFileFormat::kPcap ? impl_->next_pcap(out) : impl_->next_pcapng(out);
  if (!more) impl_->done = true;
  return more;
}

CaptureFileFormat PcapReader::format() const {
  return impl_->format;
}
const std::string& PcapReader::name() const {
  return impl_->name;
}
const std::string& PcapReader::first_interface_description() const {
  return impl_->first_accepted_description;
}
std::uint64_t PcapReader::bytes_read() const {
  return impl_->offset;
}
std::uint64_t PcapReader::size() const {
  return impl_->size;
}

}  // namespace rtu
