// Every import path keeps every byte: decoding a capture gives records whose bytes,
// concatenated in output order, are exactly the bytes the capture holds. Each reader is fed
// the same bus (frames, glued frames, a long run of garbage, line errors), then the exports
// are read back the same way.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "capture/byte_output.hpp"
#include "capture/pcap_format.hpp"
#include "capture/pcap_writer.hpp"
#include "capture/pcapng_writer.hpp"
#include "capture/rtac_serial.hpp"
#include "capture/upper_pdu.hpp"
#include "capture_test_files.hpp"
#include "core/crc16.hpp"
#include "pipeline/replay.hpp"
#include "report/pcap_export.hpp"
#include "text_capture_lines.hpp"

namespace rtu {
namespace {

using test::CollectingSink;
using testing::TempDir;

using Bytes = std::vector<std::uint8_t>;

constexpr Nanos kMs = kNanosPerMilli;
constexpr Nanos kStart = 1'700'000'000 * kNanosPerSecond;  // pcap cannot hold times before 1970

Bytes& append_crc(Bytes& adu) {
  const std::uint16_t crc = crc16(adu);
  adu.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  adu.push_back(static_cast<std::uint8_t>(crc >> 8U));
  return adu;
}

// A read-holding-registers response of `count` data bytes (255 bytes long at count 250).
Bytes long_response(std::uint8_t slave, std::uint8_t count) {
  Bytes adu = {slave, 0x03, count};
  for (unsigned i = 0; i < count; ++i) adu.push_back(static_cast<std::uint8_t>(i * 7U + slave));
  return append_crc(adu);
}

// Bytes that form no frame (checked by the tests that use them: they come out as noise).
Bytes garbage(std::size_t n) {
  Bytes out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(static_cast<std::uint8_t>(0xE5U ^ (i * 29U)));
  return out;
}

Bytes joined(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

Bytes bytes_of(const Record& r) {
  return {r.bytes().begin(), r.bytes().end()};
}

const Bytes kRequest = {0x01, 0x03, 0x00, 0x32, 0x00, 0x03, 0xA4, 0x04};
const Bytes kResponse = {0x01, 0x03, 0x06, 0xEA, 0x60, 0xC3, 0x50, 0xDB, 0x6C, 0xD1, 0x3F};

// One read() of the bus: when it completed, what it returned, a line error on its last byte.
struct Read {
  Nanos t_end = 0;
  Bytes bytes;
  std::uint8_t last_byte_errors = kLineOk;
};

// The bus every reader is fed: a transaction, the same glued into one read, a run of
// garbage longer than a record holds, a frame split over two reads, a byte with a parity
// error.
std::vector<Read> sample_bus() {
  return {
      {kStart + 10 * kMs, kRequest},
      {kStart + 60 * kMs, kResponse},
      {kStart + 200 * kMs, joined({kRequest, kResponse})},
      {kStart + 900 * kMs, garbage(600)},
      {kStart + 1500 * kMs, Bytes(kRequest.begin(), kRequest.begin() + 3)},
      {kStart + 1505 * kMs, Bytes(kRequest.begin() + 3, kRequest.end())},
      {kStart + 1600 * kMs, Bytes{0x01, 0x03, 0x02, 0x00}, kParityError},
  };
}

Bytes all_bytes(const std::vector<Read>& reads) {
  Bytes out;
  for (const auto& read : reads) out.insert(out.end(), read.bytes.begin(), read.bytes.end());
  return out;
}

std::vector<Record> decode(const std::string& path) {
  CollectingSink sink;
  ReplayOptions options;
  options.show_warnings = false;
  replay_capture(path, options, sink);
  return sink.records;
}

// Every input byte is in exactly one record, in input order, and the records are numbered
// in the order they leave.
void expect_every_byte_once(const std::vector<Record>& records, const Bytes& input) {
  std::size_t total = 0;
  Bytes output;
  for (std::size_t i = 0; i < records.size(); ++i) {
    total += records[i].size;
    const auto bytes = records[i].bytes();
    output.insert(output.end(), bytes.begin(), bytes.end());
    EXPECT_EQ(records[i].seq, i);
  }
  EXPECT_EQ(total, input.size());
  EXPECT_EQ(output, input);
}

// 1700000000.010000000 01 03 ...; the last byte's line error cannot be written in text.
std::string text_capture(const std::vector<Read>& reads) {
  std::string out = "# baud=9600 parity=E stop=1\n";
  for (const auto& read : reads) out += test::text_hex_line(read.t_end, read.bytes);
  return out;
}

// One row per byte, its start counted back from the end of the read.
std::string saleae_capture(const std::vector<Read>& reads, bool data_table) {
  const Nanos char_time = LineSettings{}.char_time();
  std::string out = data_table ? "name,type,start_time,duration,\"data\",\"error\"\n"
                               : "Time [s],Value,Parity Error,Framing Error\n";
  for (const auto& read : reads) {
    const std::size_t n = read.bytes.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Nanos start = read.t_end - static_cast<Nanos>(n - i) * char_time;
      const bool parity = i + 1 == n && read.last_byte_errors == kParityError;
      if (data_table) {
        out += fmt::format("\"Async 1\",\"data\",{},{},0x{:02X},{}\n", test::decimal_seconds(start),
                           test::decimal_seconds(char_time), read.bytes[i], parity ? "parity" : "");
      } else {
        out += fmt::format("{},0x{:02X},{},\n", test::decimal_seconds(start), read.bytes[i],
                           parity ? "Error" : "");
      }
    }
  }
  return out;
}

// RTAC serial records as rtuscope's raw export writes them: a read whose last byte had a
// line error is two records with the read's time, and an event without bytes flags the
// byte after it.
template <typename Write>
void write_rtac_reads(const std::vector<Read>& reads, Write&& write) {
  Bytes record;
  for (const auto& read : reads) {
    const auto clean = std::span(read.bytes).first(read.bytes.size() - 1);
    const auto last = std::span(read.bytes).last(1);
    build_rtac_record(read.t_end, RtacEvent::kDataRxStart, 0, clean, record);
    write(read.t_end, record);
    const auto event =
        read.last_byte_errors == kParityError ? RtacEvent::kParityError : RtacEvent::kDataRxStart;
    build_rtac_record(read.t_end, event, 0, last, record);
    write(read.t_end, record);
    build_rtac_record(read.t_end + kMs, RtacEvent::kStatusChange, 0, {}, record);
    write(read.t_end + kMs, record);
  }
}

TEST(ImportBytesKept, TextHex) {
  TempDir dir;
  const auto reads = sample_bus();
  const auto records = decode(dir.write("bus.hex", text_capture(reads)));
  expect_every_byte_once(records, all_bytes(reads));
}

TEST(ImportBytesKept, SaleaeLegacyAndDataTable) {
  TempDir dir;
  const auto reads = sample_bus();
  expect_every_byte_once(decode(dir.write("legacy.csv", saleae_capture(reads, false))),
                         all_bytes(reads));
  expect_every_byte_once(decode(dir.write("table.csv", saleae_capture(reads, true))),
                         all_bytes(reads));
}

TEST(ImportBytesKept, RtacSerialInPcapngAndClassicPcap) {
  TempDir dir;
  const auto reads = sample_bus();
  const auto ng_path = (dir.path() / "raw.pcapng").string();
  {
    PcapngWriter w(std::make_unique<FileOutput>(ng_path));
    const auto raw = w.add_interface({pcap::kLinkTypeRtacSerial, "", "RS-485 9600 8E1", 9, 0});
    write_rtac_reads(reads, [&](Nanos t, const Bytes& rec) { w.write_packet(raw, t, rec); });
    Bytes complete;
    build_rtac_record(kStart + 5 * kNanosPerSecond, RtacEvent::kCaptureComplete, 0, {}, complete);
    w.write_packet(raw, kStart + 5 * kNanosPerSecond, complete);
  }
  expect_every_byte_once(decode(ng_path), all_bytes(reads));

  const auto pcap_path = (dir.path() / "raw.pcap").string();
  {
    PcapWriter w(std::make_unique<FileOutput>(pcap_path), pcap::kLinkTypeRtacSerial);
    write_rtac_reads(reads, [&](Nanos t, const Bytes& rec) { w.write_packet(t, rec); });
  }
  expect_every_byte_once(decode(pcap_path), all_bytes(reads));
}

// A tool with a snap length below a record's length keeps only its start: those bytes are
// not in the file, and the user is told, in the capture's warnings.
TEST(ImportBytesKept, RecordsCutBySnapLengthAreReported) {
  TempDir dir;
  const auto path = (dir.path() / "cut.pcapng").string();
  Bytes record;
  {
    PcapngWriter w(std::make_unique<FileOutput>(path));
    const auto raw = w.add_interface({pcap::kLinkTypeRtacSerial, "", "", 9, 0});
    build_rtac_record(kStart, RtacEvent::kDataRxStart, 0, kRequest, record);
    w.write_packet(raw, kStart, record);
    build_rtac_record(kStart + kNanosPerSecond, RtacEvent::kDataRxStart, 0, kResponse, record);
    PcapngPacketMeta cut;
    cut.original_length = static_cast<std::uint32_t>(record.size() + 20);
    w.write_packet(raw, kStart + kNanosPerSecond, record, cut);
    w.write_packet(raw, kStart + 2 * kNanosPerSecond, record, cut);
  }
  CollectingSink sink;
  ReplayOptions options;
  options.show_warnings = false;
  const CaptureInfo info = replay_capture(path, options, sink);
  expect_every_byte_once(sink.records, joined({kRequest, kResponse, kResponse}));
  // The file declares no line settings either: that is the other warning.
  std::vector<std::string> cut_warnings;
  for (const auto& w : info.warnings) {
    if (w.find("record cut") != std::string::npos) cut_warnings.push_back(w);
  }
  ASSERT_EQ(cut_warnings.size(), 1U);
  EXPECT_NE(cut_warnings[0].find("record cut to 23 of its 43 bytes"), std::string::npos)
      << cut_warnings[0];
  EXPECT_NE(cut_warnings[0].find("(2 records cut)"), std::string::npos) << cut_warnings[0];

  const auto whole = (dir.path() / "whole.pcapng").string();
  {
    PcapngWriter w(std::make_unique<FileOutput>(whole));
    const auto raw = w.add_interface({pcap::kLinkTypeRtacSerial, "", "", 9, 0});
    w.write_packet(raw, kStart, record);
  }
  for (const auto& w : replay_capture(whole, options, sink).warnings) {
    EXPECT_EQ(w.find("record cut"), std::string::npos) << w;
  }
}

// Decodes `input` and exports the records to `out_name`; returns the export's path.
std::string export_capture(const TempDir& dir, const std::string& input,
                           const std::string& out_name, const PcapExportOptions& options) {
  const auto out_path = (dir.path() / out_name).string();
  PcapExportSink sink(std::make_unique<FileOutput>(out_path), options);
  ReplayOptions replay;
  replay.show_warnings = false;
  if (options.raw) replay.on_chunk = [&sink](const Chunk& chunk) { sink.on_chunk(chunk); };
  replay_capture(input, replay, sink);
  return out_path;
}

TEST(ImportBytesKept, ExportsReadBack) {
  TempDir dir;
  const auto reads = sample_bus();
  const auto input = dir.write("bus.hex", text_capture(reads));
  const auto frames = export_capture(dir, input, "frames.pcapng", {});
  expect_every_byte_once(decode(frames), all_bytes(reads));
  const auto raw = export_capture(dir, input, "raw.pcapng", {PcapExportFormat::kPcapng, true});
  expect_every_byte_once(decode(raw), all_bytes(reads));
  const auto classic = export_capture(dir, input, "frames.pcap", {PcapExportFormat::kPcap, false});
  expect_every_byte_once(decode(classic), all_bytes(reads));
  // An export of an export holds the same bytes again.
  const auto again = export_capture(dir, frames, "again.pcapng", {});
  expect_every_byte_once(decode(again), all_bytes(reads));
}

// Upper-PDU records as another tool may write them: frame records holding more than one
// frame, or more bytes than any frame.
struct PduRecord {
  Bytes bytes;
  std::string_view dissector = upper_pdu::kModbusRtuDissector;
};

std::string upper_pdu_capture(const TempDir& dir, const std::vector<PduRecord>& pdus) {
  const auto path = (dir.path() / "pdus.pcapng").string();
  PcapngWriter w(std::make_unique<FileOutput>(path));
  const auto id = w.add_interface({pcap::kLinkTypeUpperPdu, "", "RS-485 9600 8E1", 9, 0});
  Bytes record;
  Nanos t = kStart;
  for (const auto& pdu : pdus) {
    build_upper_pdu(pdu.bytes, {pdu.dissector, PduDirection::kUnknown, ""}, record);
    w.write_packet(id, t, record);
    t += 2 * kNanosPerSecond;  // records far apart: each gap is a silence
  }
  return path;
}

struct Expected {
  RecordKind kind;
  Bytes bytes;
};

void expect_records(const std::vector<Record>& records, const std::vector<Expected>& expected) {
  ASSERT_EQ(records.size(), expected.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    EXPECT_EQ(records[i].kind, expected[i].kind) << "record " << i;
    EXPECT_EQ(bytes_of(records[i]), expected[i].bytes) << "record " << i;
  }
}

TEST(ImportBytesKept, OversizeUpperPduFramesAreSplitIntoFramesAndNoise) {
  TempDir dir;
  const Bytes first = long_response(0x11, 250);   // 255 bytes
  const Bytes second = long_response(0x12, 250);  // 255 bytes
  const Bytes record_300 = joined({first, kRequest, garbage(37)});
  const Bytes record_600 = joined({first, second, garbage(90)});
  ASSERT_EQ(record_300.size(), 300U);
  ASSERT_EQ(record_600.size(), 600U);
  const auto path = upper_pdu_capture(dir, {{kRequest}, {record_300}, {record_600}});

  const auto records = decode(path);
  expect_records(records, {{RecordKind::kFrame, kRequest},
                           {RecordKind::kFrame, first},
                           {RecordKind::kFrame, kRequest},
                           {RecordKind::kNoise, garbage(37)},
                           {RecordKind::kFrame, first},
                           {RecordKind::kFrame, second},
                           {RecordKind::kNoise, garbage(90)}});
  expect_every_byte_once(records, joined({kRequest, record_300, record_600}));
  for (const auto& r : records) {
    if (r.kind == RecordKind::kFrame) {
      EXPECT_TRUE(r.crc_ok);
    }
    EXPECT_FALSE(r.issues.has(IssueId::kTooLong));
  }
  // Each record's pieces follow one another at the line rate from the record's time; the
  // timestamps show no silence inside a record.
  const Nanos char_time = LineSettings{}.char_time();
  EXPECT_EQ(records[1].t_start, kStart + 2 * kNanosPerSecond);
  EXPECT_EQ(records[2].t_start, records[1].t_end);
  EXPECT_EQ(records[3].t_end, records[1].t_start + 300 * char_time);
  EXPECT_NE(records[1].gap_before, kUnknownTime);
  EXPECT_EQ(records[2].gap_before, kUnknownTime);
  EXPECT_EQ(records[5].gap_before, kUnknownTime);
  EXPECT_FALSE(records[5].issues.has(IssueId::kT35));
}

TEST(ImportBytesKept, CrcValidOversizeFrameIsTooLongThenNoise) {
  TempDir dir;
  // One frame the CRC confirms over all 300 bytes, longer than RTU allows (a vendor's
  // function code; its length follows no rule).
  Bytes frame = {0x05, 0x41};
  for (unsigned i = 0; i < 296; ++i) frame.push_back(static_cast<std::uint8_t>(i));
  append_crc(frame);
  ASSERT_EQ(frame.size(), 300U);
  const Bytes noise_300 = garbage(300);
  const auto path = upper_pdu_capture(dir, {{frame}, {noise_300, "data"}});

  const auto records = decode(path);
  const Bytes head(frame.begin(), frame.begin() + 256);
  const Bytes tail(frame.begin() + 256, frame.end());
  expect_records(records, {{RecordKind::kFrame, head},
                           {RecordKind::kNoise, tail},
                           {RecordKind::kNoise, Bytes(noise_300.begin(), noise_300.begin() + 256)},
                           {RecordKind::kNoise, Bytes(noise_300.begin() + 256, noise_300.end())}});
  expect_every_byte_once(records, joined({frame, noise_300}));
  EXPECT_TRUE(records[0].issues.has(IssueId::kTooLong));
  EXPECT_FALSE(records[0].issues.has(IssueId::kCrc)) << "its CRC holds over all 300 bytes";
  EXPECT_FALSE(records[0].crc_ok) << "the record does not hold the CRC: no PDU decoding";
  EXPECT_EQ(records[0].t_end, records[1].t_start);
  EXPECT_TRUE(records[1].issues.has(IssueId::kNoiseBytes));
}

TEST(ImportBytesKept, DamagedOversizeFrameIsNoise) {
  TempDir dir;
  Bytes frame = {0x05, 0x41};
  for (unsigned i = 0; i < 296; ++i) frame.push_back(static_cast<std::uint8_t>(i));
  append_crc(frame);
  frame[100] ^= 0x01U;  // the CRC no longer holds
  const auto records = decode(upper_pdu_capture(dir, {{frame}}));
  for (const auto& r : records) EXPECT_EQ(r.kind, RecordKind::kNoise);
  expect_every_byte_once(records, frame);
}

TEST(ImportBytesKept, OversizeUpperPduRecordsReadBackFromTheirExport) {
  TempDir dir;
  const Bytes record_600 =
      joined({long_response(0x11, 250), long_response(0x12, 250), garbage(90)});
  const auto input = upper_pdu_capture(dir, {{kRequest}, {record_600}});
  const auto exported = export_capture(dir, input, "export.pcapng", {});
  expect_every_byte_once(decode(exported), joined({kRequest, record_600}));
}

}  // namespace
}  // namespace rtu

namespace rtu {
namespace {

// Wireshark writes upper-PDU records with no payload (a dissector's empty PDU). They hold
// no byte: nothing to decode, and no 0-byte "frame" (slave 0, function 0) that would
// wait for an answer and time out.
TEST(ImportBytesKept, EmptyUpperPduRecordsHoldNoFrame) {
  TempDir dir;
  const auto path = upper_pdu_capture(dir, {{kRequest}, {Bytes{}}, {kResponse}, {Bytes{}, "data"}});
  const auto records = decode(path);
  expect_records(records, {{RecordKind::kFrame, kRequest}, {RecordKind::kFrame, kResponse}});
}

}  // namespace
}  // namespace rtu
