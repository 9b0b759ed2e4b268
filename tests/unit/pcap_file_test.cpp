// pcap / pcapng writers and the one reader for both: round trips in both byte orders and
// resolutions, hand-made blocks (2^-n resolution, tsoffset, unknown blocks), and damaged
// files cut or corrupted at every offset.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "capture/byte_order.hpp"
#include "capture/byte_output.hpp"
#include "capture/pcap_format.hpp"
#include "capture/pcap_reader.hpp"
#include "capture/pcap_writer.hpp"
#include "capture/pcapng_writer.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

using Bytes = std::vector<std::uint8_t>;

struct Packet {
  std::uint16_t link_type = 0;
  std::uint32_t interface_id = 0;
  std::uint32_t section = 0;
  Nanos t = 0;
  Nanos resolution = 0;
  Bytes data;
  std::string comment;
  std::optional<std::uint32_t> flags;
  std::string interface_name;
  std::string interface_description;
  std::uint64_t offset = 0;
};

struct ReadResult {
  std::vector<Packet> packets;
  std::optional<std::string> error;
};

ReadResult read_all(const Bytes& file, std::vector<std::uint16_t> accepted = {}) {
  ReadResult result;
  try {
    auto in = std::make_unique<std::istringstream>(std::string(file.begin(), file.end()));
    PcapReader reader(std::move(in), "mem.pcapng", std::move(accepted));
    CapturePacket p;
    while (reader.next(p)) {
      result.packets.push_back({p.link_type, p.interface_id, p.section, p.t, p.resolution,
                                Bytes(p.data.begin(), p.data.end()), std::string(p.comment),
                                p.flags, std::string(p.interface_name),
                                std::string(p.interface_description), p.offset});
    }
    EXPECT_FALSE(reader.next(p)) << "next() after the end must stay false";
  } catch (const InputError& e) {
    result.error = e.what();
  }
  return result;
}

const Bytes kRequest = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};
const Bytes kResponse = {0x01, 0x03, 0x02, 0x12, 0x34, 0xB5, 0x33};
const Bytes kChunk = {0x11, 0x06};  // 3 bytes incl. odd length → padding exercised
constexpr Nanos kT0 = 1'700'000'000'123'456'789;

struct Written {
  Bytes bytes;
  std::vector<std::size_t> block_ends;  // file size after each block
};

Written write_sample_pcapng(ByteOrder order) {
  auto out = std::make_unique<MemoryOutput>();
  const MemoryOutput& mem = *out;
  Written w;
  PcapngWriter writer(std::move(out), order);
  w.block_ends.push_back(mem.bytes().size());
  const auto frames =
      writer.add_interface({pcap::kLinkTypeUpperPdu, "/dev/ttyUSB0", "RS-485 9600 8E1", 9, 0});
  w.block_ends.push_back(mem.bytes().size());
  writer.write_packet(frames, kT0, kRequest, {"crc; t3.5", pcap::kFlagsOutbound, 0});
  w.block_ends.push_back(mem.bytes().size());
  const auto raw = writer.add_interface({pcap::kLinkTypeRtacSerial, "raw", "", 6, 0});
  w.block_ends.push_back(mem.bytes().size());
  writer.write_packet(raw, kT0 + 5'000'999, Bytes{0x11, 0x06, 0x00});
  w.block_ends.push_back(mem.bytes().size());
  writer.write_packet(frames, kT0 + 10'000'000, kResponse, {"", pcap::kFlagsInbound, 0});
  w.block_ends.push_back(mem.bytes().size());
  w.bytes = mem.bytes();
  return w;
}

void expect_sample(const ReadResult& r) {
  ASSERT_FALSE(r.error) << *r.error;
  ASSERT_EQ(r.packets.size(), 3U);
  EXPECT_EQ(r.packets[0].link_type, pcap::kLinkTypeUpperPdu);
  EXPECT_EQ(r.packets[0].interface_id, 0U);
  EXPECT_EQ(r.packets[0].t, kT0);
  EXPECT_EQ(r.packets[0].resolution, 1);
  EXPECT_EQ(r.packets[0].data, kRequest);
  EXPECT_EQ(r.packets[0].comment, "crc; t3.5");
  EXPECT_EQ(r.packets[0].flags, pcap::kFlagsOutbound);
  EXPECT_EQ(r.packets[0].interface_name, "/dev/ttyUSB0");
  EXPECT_EQ(r.packets[0].interface_description, "RS-485 9600 8E1");
  EXPECT_EQ(r.packets[1].link_type, pcap::kLinkTypeRtacSerial);
  EXPECT_EQ(r.packets[1].interface_id, 1U);
  EXPECT_EQ(r.packets[1].t, (kT0 + 5'000'999) / 1000 * 1000);  // truncated to µs
  EXPECT_EQ(r.packets[1].resolution, 1000);
  EXPECT_EQ(r.packets[1].data, (Bytes{0x11, 0x06, 0x00}));
  EXPECT_EQ(r.packets[1].comment, "");
  EXPECT_FALSE(r.packets[1].flags);
  EXPECT_EQ(r.packets[1].interface_name, "raw");
  EXPECT_EQ(r.packets[2].t, kT0 + 10'000'000);
  EXPECT_EQ(r.packets[2].data, kResponse);
  EXPECT_EQ(r.packets[2].flags, pcap::kFlagsInbound);
}

TEST(Pcapng, RoundTripLittleEndian) {
  expect_sample(read_all(write_sample_pcapng(ByteOrder::kLittle).bytes));
}

TEST(Pcapng, RoundTripBigEndian) {
  const Written w = write_sample_pcapng(ByteOrder::kBig);
  EXPECT_EQ(w.bytes[8], 0x1A);  // byte-order magic as written big-endian
  expect_sample(read_all(w.bytes));
}

TEST(Pcapng, WriterLayoutMatchesTheSpec) {
  const Bytes b = write_sample_pcapng(ByteOrder::kLittle).bytes;
  // SHB: type, length, magic, version 1.0, section length -1, shb_userappl.
  EXPECT_EQ(load_u32(b, 0, ByteOrder::kLittle), pcap::kBlockSectionHeader);
  const std::uint32_t shb_length = load_u32(b, 4, ByteOrder::kLittle);
  EXPECT_EQ(shb_length % 4, 0U);
  EXPECT_EQ(load_u32(b, 8, ByteOrder::kLittle), pcap::kByteOrderMagic);
  EXPECT_EQ(load_u16(b, 12, ByteOrder::kLittle), 1U);
  EXPECT_EQ(load_u64(b, 16, ByteOrder::kLittle), ~std::uint64_t{0});
  EXPECT_EQ(load_u16(b, 24, ByteOrder::kLittle), pcap::kShbUserAppl);
  const std::string appl(b.begin() + 28, b.begin() + 28 + load_u16(b, 26, ByteOrder::kLittle));
  EXPECT_EQ(appl, "rtuscope " RTUSCOPE_VERSION);
  EXPECT_EQ(load_u32(b, shb_length - 4, ByteOrder::kLittle), shb_length);
  // IDB: link type 252, if_tsresol 9 present.
  EXPECT_EQ(load_u32(b, shb_length, ByteOrder::kLittle), pcap::kBlockInterfaceDescription);
  EXPECT_EQ(load_u16(b, shb_length + 8, ByteOrder::kLittle), pcap::kLinkTypeUpperPdu);
}

TEST(Pcapng, SeveralSectionsRestartInterfaces) {
  Bytes file = write_sample_pcapng(ByteOrder::kLittle).bytes;
  const Bytes second = write_sample_pcapng(ByteOrder::kBig).bytes;
  file.insert(file.end(), second.begin(), second.end());
  const ReadResult r = read_all(file);
  ASSERT_FALSE(r.error) << *r.error;
  ASSERT_EQ(r.packets.size(), 6U);
  EXPECT_EQ(r.packets[3].section, 1U);
  EXPECT_EQ(r.packets[3].interface_id, 0U);
  EXPECT_EQ(r.packets[3].data, kRequest);
  EXPECT_EQ(r.packets[4].link_type, pcap::kLinkTypeRtacSerial);
  EXPECT_EQ(r.packets[5].t, kT0 + 10'000'000);
}

// Hand-made blocks for what our writer never produces.
Bytes block(std::uint32_t type, const Bytes& body, ByteOrder o = ByteOrder::kLittle) {
  Bytes b;
  append<std::uint32_t>(b, type, o);
  append<std::uint32_t>(b, static_cast<std::uint32_t>(12 + body.size()), o);
  b.insert(b.end(), body.begin(), body.end());
  append<std::uint32_t>(b, static_cast<std::uint32_t>(12 + body.size()), o);
  return b;
}

Bytes shb(ByteOrder o = ByteOrder::kLittle) {
  Bytes body;
  append<std::uint32_t>(body, pcap::kByteOrderMagic, o);
  append<std::uint16_t>(body, 1, o);
  append<std::uint16_t>(body, 0, o);
  append<std::uint64_t>(body, ~std::uint64_t{0}, o);
  return block(pcap::kBlockSectionHeader, body, o);
}

Bytes idb(std::uint16_t link_type, std::optional<std::uint8_t> tsresol,
          std::optional<std::int64_t> tsoffset) {
  Bytes body;
  append<std::uint16_t>(body, link_type, ByteOrder::kLittle);
  append<std::uint16_t>(body, 0, ByteOrder::kLittle);
  append<std::uint32_t>(body, 0, ByteOrder::kLittle);
  if (tsresol) {
    append<std::uint16_t>(body, pcap::kIfTsResol, ByteOrder::kLittle);
    append<std::uint16_t>(body, 1, ByteOrder::kLittle);
    body.insert(body.end(), {*tsresol, 0, 0, 0});
  }
  if (tsoffset) {
    append<std::uint16_t>(body, pcap::kIfTsOffset, ByteOrder::kLittle);
    append<std::uint16_t>(body, 8, ByteOrder::kLittle);
    append<std::uint64_t>(body, static_cast<std::uint64_t>(*tsoffset), ByteOrder::kLittle);
  }
  append<std::uint32_t>(body, 0, ByteOrder::kLittle);
  return block(pcap::kBlockInterfaceDescription, body);
}

Bytes epb(std::uint32_t interface_id, std::uint64_t ticks, const Bytes& data) {
  Bytes body;
  append<std::uint32_t>(body, interface_id, ByteOrder::kLittle);
  append<std::uint32_t>(body, static_cast<std::uint32_t>(ticks >> 32U), ByteOrder::kLittle);
  append<std::uint32_t>(body, static_cast<std::uint32_t>(ticks), ByteOrder::kLittle);
  append<std::uint32_t>(body, static_cast<std::uint32_t>(data.size()), ByteOrder::kLittle);
  append<std::uint32_t>(body, static_cast<std::uint32_t>(data.size()), ByteOrder::kLittle);
  body.insert(body.end(), data.begin(), data.end());
  while (body.size() % 4 != 0) body.push_back(0);
  return block(pcap::kBlockEnhancedPacket, body);
}

Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

TEST(Pcapng, AbsentTsresolMeansMicroseconds) {
  const ReadResult r = read_all(concat(
      {shb(), idb(252, std::nullopt, std::nullopt), epb(0, 1'700'000'000'123'456ULL, kRequest)}));
  ASSERT_FALSE(r.error) << *r.error;
  ASSERT_EQ(r.packets.size(), 1U);
  EXPECT_EQ(r.packets[0].t, 1'700'000'000'123'456'000);
  EXPECT_EQ(r.packets[0].resolution, 1000);
}

TEST(Pcapng, BinaryResolutionAndOffset) {
  // 2^-20 s units; 3.5 s = 3.5 × 2^20 ticks; if_tsoffset adds 1000 s.
  const std::uint64_t ticks = (std::uint64_t{7} << 20U) / 2;
  const ReadResult r =
      read_all(concat({shb(), idb(252, 0x80 | 20, 1000), epb(0, ticks, kRequest)}));
  ASSERT_FALSE(r.error) << *r.error;
  ASSERT_EQ(r.packets.size(), 1U);
  EXPECT_EQ(r.packets[0].t, 1003'500'000'000);
  EXPECT_EQ(r.packets[0].resolution, 953);  // 1e9 / 2^20, rounded down
}

TEST(Pcapng, DecimalResolutionsFinerAndCoarserThanNanoseconds) {
  EXPECT_EQ(pcapng_ticks_to_nanos(12345, 3, 0), 12'345'000'000);
  EXPECT_EQ(pcapng_ticks_to_nanos(12345, 12, 0), 12);  // picoseconds, truncated
  EXPECT_EQ(pcapng_ticks_to_nanos(1, 0, -1), 0);
  EXPECT_EQ(pcapng_ticks_to_nanos(3, 0x81, 0), 1'500'000'000);  // 2^-1 s
  EXPECT_EQ(pcapng_ticks_to_nanos(~std::uint64_t{0}, 0x80 | 63, 0), 1'999'999'999);
  EXPECT_FALSE(pcapng_ticks_to_nanos(~std::uint64_t{0}, 9, 0));  // > int64 ns
  EXPECT_FALSE(pcapng_ticks_to_nanos(1, 0, std::int64_t{1} << 62));
}

// The reader converts the common interfaces (decimal if_tsresol up to nanoseconds, no
// offset) in line: every interface and tick count gives what the general conversion gives,
// a timestamp past int64 nanoseconds included (an error naming the offset of the ticks).
TEST(Pcapng, PacketTimesAreTheGeneralConversionsForEveryInterface) {
  const std::uint64_t big = std::uint64_t{1} << 62U;
  for (const std::optional<std::uint8_t> tsresol :
       {std::optional<std::uint8_t>{}, std::optional<std::uint8_t>{0},
        std::optional<std::uint8_t>{3}, std::optional<std::uint8_t>{6},
        std::optional<std::uint8_t>{9}, std::optional<std::uint8_t>{12},
        std::optional<std::uint8_t>{0x80 | 20}}) {
    for (const std::optional<std::int64_t> tsoffset :
         {std::optional<std::int64_t>{}, std::optional<std::int64_t>{-5}}) {
      for (const std::uint64_t ticks : {std::uint64_t{0}, std::uint64_t{1'700'000'000'123'456},
                                        big / 1000, big, ~std::uint64_t{0}}) {
        SCOPED_TRACE(fmt::format("tsresol {} tsoffset {} ticks {}", tsresol.value_or(6),
                                 tsoffset.value_or(0), ticks));
        const auto want = pcapng_ticks_to_nanos(ticks, tsresol.value_or(6), tsoffset.value_or(0));
        const Bytes file = concat({shb(), idb(252, tsresol, tsoffset), epb(0, ticks, kRequest)});
        const ReadResult r = read_all(file);
        if (want) {
          ASSERT_FALSE(r.error) << *r.error;
          ASSERT_EQ(r.packets.size(), 1U);
          EXPECT_EQ(r.packets[0].t, *want);
        } else {
          ASSERT_TRUE(r.error);
          EXPECT_NE(r.error->find("does not fit in 64-bit nanoseconds"), std::string::npos)
              << *r.error;
          // The ticks sit 12 bytes into the packet block, which follows the SHB and the IDB.
          const std::size_t ticks_at = shb().size() + idb(252, tsresol, tsoffset).size() + 12;
          EXPECT_NE(r.error->find(fmt::format("offset {}", ticks_at)), std::string::npos)
              << *r.error;
        }
      }
    }
  }
}

TEST(Pcapng, UnknownBlocksAreSkippedByLength) {
  const Bytes custom = block(0x00000BAD, Bytes(20, 0xEE));
  const Bytes statistics = block(0x00000005, Bytes(16, 0));
  const ReadResult r = read_all(concat({shb(), custom, idb(252, 9, std::nullopt), statistics,
                                        epb(0, 5, kRequest), custom, epb(0, 6, kResponse)}));
  ASSERT_FALSE(r.error) << *r.error;
  ASSERT_EQ(r.packets.size(), 2U);
  EXPECT_EQ(r.packets[1].data, kResponse);
  EXPECT_EQ(r.packets[1].t, 6);
}

TEST(Pcapng, UnsupportedLinkTypeNamesTheInterfaceBlock) {
  const Bytes head = concat({shb(), idb(252, 9, std::nullopt)});
  const Bytes ethernet = idb(1, 9, std::nullopt);
  const Bytes file = concat({head, ethernet, epb(0, 1, kRequest), epb(1, 2, kRequest)});
  const ReadResult r = read_all(file, {250, 252});
  ASSERT_TRUE(r.error);
  EXPECT_EQ(r.packets.size(), 1U);  // the 252 packet before it is delivered
  EXPECT_NE(r.error->find("link type 1 "), std::string::npos) << *r.error;
  EXPECT_NE(r.error->find(fmt::format("block at offset {}", head.size())), std::string::npos)
      << *r.error;
  EXPECT_NE(r.error->find("expected 250 or 252"), std::string::npos) << *r.error;
  // Without restrictions the same file reads completely.
  EXPECT_EQ(read_all(file).packets.size(), 2U);
}

TEST(Pcapng, PacketOnUndeclaredInterface) {
  const Bytes head = concat({shb(), idb(252, 9, std::nullopt)});
  const ReadResult r = read_all(concat({head, epb(3, 1, kRequest)}));
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->find(fmt::format("offset {}: packet on interface 3", head.size() + 8)),
            std::string::npos)
      << *r.error;
}

TEST(Pcapng, ErrorMessagesNameFileOffsetAndExpectation) {
  const Bytes head = concat({shb(), idb(252, 9, std::nullopt)});
  Bytes tiny = concat({head, epb(0, 1, kRequest)});
  store<std::uint32_t>(tiny, head.size() + 4, 8, ByteOrder::kLittle);
  ReadResult r = read_all(tiny);
  ASSERT_TRUE(r.error);
  EXPECT_EQ(*r.error, fmt::format("mem.pcapng: offset {}: block length 8 is smaller than a "
                                  "block header and trailer (12 bytes)",
                                  head.size() + 4));

  Bytes small_epb = concat({head, block(pcap::kBlockEnhancedPacket, Bytes(8, 0))});
  r = read_all(small_epb);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->find("enhanced packet block length 20 is smaller than its fixed fields"),
            std::string::npos)
      << *r.error;

  Bytes trailer = concat({head, epb(0, 1, kRequest)});
  trailer[trailer.size() - 4] ^= 0x40;
  r = read_all(trailer);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->find(fmt::format("offset {}: trailing block length", trailer.size() - 4)),
            std::string::npos)
      << *r.error;

  r = read_all(Bytes{'h', 'e', 'l', 'l', 'o'});
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->find("mem.pcapng: offset 0: not a pcap or pcapng file"), std::string::npos);
}

// Cutting the file anywhere: every packet whose block is whole comes out, then an error
// naming an offset, unless the cut falls exactly between blocks.
TEST(Pcapng, TruncatedAtEveryOffset) {
  for (const ByteOrder order : {ByteOrder::kLittle, ByteOrder::kBig}) {
    const Written w = write_sample_pcapng(order);
    const std::vector<std::size_t> packet_ends = {w.block_ends[2], w.block_ends[4],
                                                  w.block_ends[5]};
    for (std::size_t cut = 0; cut < w.bytes.size(); ++cut) {
      const ReadResult r =
          read_all(Bytes(w.bytes.begin(), w.bytes.begin() + static_cast<long>(cut)));
      std::size_t whole = 0;
      for (const std::size_t end : packet_ends) whole += end <= cut ? 1 : 0;
      EXPECT_EQ(r.packets.size(), whole) << "cut at " << cut;
      const bool at_boundary =
          cut > 0 && std::find(w.block_ends.begin(), w.block_ends.end(), cut) != w.block_ends.end();
      EXPECT_EQ(r.error.has_value(), !at_boundary) << "cut at " << cut;
      if (r.error) {
        EXPECT_EQ(r.error->rfind("mem.pcapng: offset ", 0), 0U) << *r.error;
      }
    }
  }
}

// Corrupting any single byte never crashes the reader and never yields a packet that was
// not written; where it fails, the message names an offset.
TEST(Pcapng, CorruptedAtEveryOffset) {
  const Written w = write_sample_pcapng(ByteOrder::kLittle);
  for (std::size_t at = 0; at < w.bytes.size(); ++at) {
    for (const unsigned flip : {0x01U, 0x80U, 0xFFU}) {
      Bytes bad = w.bytes;
      bad[at] = static_cast<std::uint8_t>(bad[at] ^ flip);
      const ReadResult r = read_all(bad);
      EXPECT_LE(r.packets.size(), 3U);
      if (r.error) {
        EXPECT_NE(r.error->find(": offset "), std::string::npos) << *r.error;
      }
    }
  }
}

Bytes write_sample_pcap(PcapResolution resolution, ByteOrder order) {
  auto out = std::make_unique<MemoryOutput>();
  const MemoryOutput& mem = *out;
  PcapWriter writer(std::move(out), pcap::kLinkTypeUpperPdu, resolution, order);
  writer.write_packet(kT0, kRequest);
  writer.write_packet(kT0 + 1, kResponse);
  return mem.bytes();
}

TEST(Pcap, RoundTripEveryMagic) {
  for (const auto resolution : {PcapResolution::kMicros, PcapResolution::kNanos}) {
    for (const ByteOrder order : {ByteOrder::kLittle, ByteOrder::kBig}) {
      const Bytes file = write_sample_pcap(resolution, order);
      const bool ns = resolution == PcapResolution::kNanos;
      const std::uint32_t magic = ns ? pcap::kMagicNanos : pcap::kMagicMicros;
      EXPECT_EQ(load_u32(file, 0, order), magic);
      EXPECT_EQ(load_u32(file, 20, order), pcap::kLinkTypeUpperPdu);
      const ReadResult r = read_all(file, {252});
      ASSERT_FALSE(r.error) << *r.error;
      ASSERT_EQ(r.packets.size(), 2U);
      const Nanos t0 = ns ? kT0 : kT0 - 789;
      EXPECT_EQ(r.packets[0].t, t0);
      EXPECT_EQ(r.packets[1].t, ns ? kT0 + 1 : t0);
      EXPECT_EQ(r.packets[0].resolution, ns ? 1 : 1000);
      EXPECT_EQ(r.packets[0].link_type, pcap::kLinkTypeUpperPdu);
      EXPECT_EQ(r.packets[0].data, kRequest);
      EXPECT_EQ(r.packets[1].data, kResponse);
      EXPECT_EQ(r.packets[1].offset, 24U + 16U + kRequest.size());
    }
  }
}

TEST(Pcap, TruncatedAtEveryOffset) {
  const Bytes file = write_sample_pcap(PcapResolution::kNanos, ByteOrder::kBig);
  const std::size_t first_end = 24 + 16 + kRequest.size();
  for (std::size_t cut = 0; cut < file.size(); ++cut) {
    const ReadResult r = read_all(Bytes(file.begin(), file.begin() + static_cast<long>(cut)));
    EXPECT_EQ(r.packets.size(), cut >= first_end ? 1U : 0U) << cut;
    EXPECT_EQ(r.error.has_value(), cut != 24 && cut != first_end) << cut;
    if (r.error) {
      EXPECT_EQ(r.error->rfind("mem.pcapng: offset ", 0), 0U) << *r.error;
    }
  }
}

TEST(Pcap, UnsupportedLinkTypeAtOffset20) {
  auto out = std::make_unique<MemoryOutput>();
  const MemoryOutput& mem = *out;
  PcapWriter writer(std::move(out), 1);
  writer.write_packet(kT0, kRequest);
  const ReadResult r = read_all(mem.bytes(), {250, 252});
  ASSERT_TRUE(r.error);
  EXPECT_EQ(*r.error, "mem.pcapng: offset 20: link type 1 is not supported; expected 250 or 252");
}

TEST(Pcap, ImplausibleRecordLength) {
  Bytes file = write_sample_pcap(PcapResolution::kMicros, ByteOrder::kLittle);
  store<std::uint32_t>(file, 24 + 8, 0x7FFFFFFF, ByteOrder::kLittle);
  const ReadResult r = read_all(file);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->find("offset 32: record length 2147483647 is implausible"), std::string::npos)
      << *r.error;
}

TEST(Writers, RejectTimesBefore1970) {
  PcapngWriter ng(std::make_unique<MemoryOutput>());
  const auto id = ng.add_interface({pcap::kLinkTypeUpperPdu, "", "", 9, 0});
  EXPECT_THROW(ng.write_packet(id, -1, kRequest), InputError);
  EXPECT_THROW(ng.write_packet(id + 1, 0, kRequest), std::out_of_range);
  PcapWriter classic(std::make_unique<MemoryOutput>(), pcap::kLinkTypeUpperPdu);
  EXPECT_THROW(classic.write_packet(-1, kRequest), InputError);
}

// A file being written holds whole blocks after each flush(), and a reader sees every
// flushed packet while the writer is still open (as after a crash).
TEST(FileOutputTest, FlushedFileIsReadableWhileOpen) {
  const auto path =
      std::filesystem::temp_directory_path() / fmt::format("rtuscope_flush_{}.pcapng", ::getpid());
  {
    PcapngWriter writer(std::make_unique<FileOutput>(path.string()));
    const auto id = writer.add_interface({pcap::kLinkTypeUpperPdu, "", "", 9, 0});
    for (int i = 0; i < 3000; ++i) {
      writer.write_packet(id, kT0 + i, kRequest, {"comment", pcap::kFlagsOutbound, 0});
      if (i % 250 != 0) continue;
      if (i % 500 == 0) writer.flush();
      // Flushed or not, the OS only ever holds whole blocks (the buffer is written whole).
      const auto size = std::filesystem::file_size(path);
      if (size == 0) continue;  // nothing handed over yet
      PcapReader reader(path.string());
      CapturePacket p;
      std::size_t n = 0;
      EXPECT_NO_THROW(while (reader.next(p))++ n) << "at packet " << i << ", size " << size;
      EXPECT_LE(n, static_cast<std::size_t>(i) + 1);
      if (i % 500 == 0) {
        EXPECT_EQ(n, static_cast<std::size_t>(i) + 1);
      }
    }
    writer.flush();
    PcapReader reader(path.string());
    CapturePacket p;
    std::size_t n = 0;
    while (reader.next(p)) ++n;
    EXPECT_EQ(n, 3000U);
  }
  std::filesystem::remove(path);
}

TEST(FileOutputTest, UncreatableFileNamesThePath) {
  try {
    FileOutput out("/nonexistent-dir/x.pcapng");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.pcapng: cannot create"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace rtu
