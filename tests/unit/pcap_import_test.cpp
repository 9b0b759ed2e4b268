#include "capture/pcap_import.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "capture/byte_output.hpp"
#include "capture/pcap_format.hpp"
#include "capture/pcapng_writer.hpp"
#include "capture/rtac_serial.hpp"
#include "capture/upper_pdu.hpp"
#include "core/input_error.hpp"
#include "pipeline/pcapng_recorder.hpp"
#include "pipeline/replay.hpp"
#include "report/pcap_export.hpp"

namespace rtu {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(PcapImport, LineSettingsAndResolutionFromTheInterfaceDescription) {
  const auto line =
      parse_line_description("Modbus RTU frames, 19200 8N2, timing resolution 16.383 ms");
  ASSERT_TRUE(line);
  EXPECT_EQ(line->baud, 19200U);
  EXPECT_EQ(line->parity, Parity::kNone);
  EXPECT_EQ(line->stop_bits, 2);
  EXPECT_EQ(parse_resolution_description("9600 8E1, timing resolution 16.383 ms"), 16'383'000);
  EXPECT_EQ(parse_resolution_description("timing resolution 0.001 ms"), 1000);
  EXPECT_FALSE(parse_line_description("RS-485 bus"));
  EXPECT_FALSE(parse_line_description("x9600 8E1"));
  EXPECT_FALSE(parse_resolution_description("timing resolution fine"));
  EXPECT_EQ(parse_timeout_description("timing resolution 1 ms; response timeout 300 ms"),
            300 * kNanosPerMilli);
  EXPECT_FALSE(parse_timeout_description("timing resolution 1 ms"));
}

struct TempFile {
  std::filesystem::path path = std::filesystem::temp_directory_path() /
                               ("rtuscope_import_" + std::to_string(::getpid()) + ".pcapng");
  ~TempFile() { std::filesystem::remove(path); }
};

// What a decode of a file was started with.
struct CaptureInfoSink final : RecordSink {
  void on_capture(const CaptureInfo& info) override { captured = info; }
  void on_record(Record& record) override { (void)record; }
  CaptureInfo captured;
};

LineSettings line_19200_8n2() {
  LineSettings line;
  line.baud = 19200;
  line.parity = Parity::kNone;
  line.stop_bits = 2;
  return line;
}

// A file of no bytes that declares 19200 8N2 and a 2 ms resolution: its decode must name
// them, not assume the Modbus default as for a file that says nothing.
void expect_line_declared(const std::string& path) {
  PcapImporter importer{CaptureFile(path)};
  PcapItem item;
  while (importer.next(item)) {
    EXPECT_EQ(item.kind, PcapItem::Kind::kEnd);
  }
  ASSERT_TRUE(importer.declared_settings());
  EXPECT_EQ(importer.declared_settings()->baud, 19200U);
  EXPECT_EQ(importer.declared_settings()->parity, Parity::kNone);
  EXPECT_EQ(importer.declared_resolution(), 2 * kNanosPerMilli);

  CaptureInfoSink sink;
  ReplayOptions options;
  options.show_warnings = false;
  replay_capture(path, options, sink);
  EXPECT_EQ(sink.captured.line.baud, 19200U);
  EXPECT_EQ(sink.captured.line.stop_bits, 2);
  EXPECT_EQ(sink.captured.timing_resolution, 2 * kNanosPerMilli);
}

// `export --raw` of a capture without bytes writes its interfaces and no packet at all.
TEST(PcapImport, AnExportWithoutPacketsStillDeclaresItsLine) {
  TempFile file;
  {
    PcapExportOptions options;
    options.raw = true;
    PcapExportSink sink(std::make_unique<FileOutput>(file.path.string()), options);
    CaptureInfo info;
    info.line = line_19200_8n2();
    info.timing_resolution = 2 * kNanosPerMilli;
    sink.on_capture(info);
    sink.on_finish();
  }
  expect_line_declared(file.path.string());
}

// A live recording of a line that stayed quiet: its interface and the end of the capture.
TEST(PcapImport, ARecordingOfAQuietLineDeclaresItsLineAndTimeout) {
  TempFile file;
  {
    PcapngRecorder recorder(file.path.string());
    SerialStatus status;
    status.resolution = 2 * kNanosPerMilli;
    recorder.add_port(0, "/dev/ttyS0", line_19200_8n2(), status, 700 * kNanosPerMilli);
    recorder.on_end(1'700'000'000 * kNanosPerSecond);
  }
  expect_line_declared(file.path.string());
  PcapImporter importer{CaptureFile(file.path.string())};
  PcapItem item;
  while (importer.next(item)) {
  }
  EXPECT_EQ(importer.declared_timeout(), 700 * kNanosPerMilli);
}

TEST(PcapImport, RawRecordsWithOneTimeAreOneChunkAndEventsFlagBytes) {
  TempFile file;
  {
    PcapngWriter w(std::make_unique<FileOutput>(file.path.string()));
    const auto raw = w.add_interface({pcap::kLinkTypeRtacSerial, "", "9600 8O1", 9, 0});
    const auto frames = w.add_interface({pcap::kLinkTypeUpperPdu, "", "", 9, 0});
    Bytes rec;
    build_rtac_record(1000, RtacEvent::kDataRxStart, 0, Bytes{0x01, 0x03}, rec);
    w.write_packet(raw, 1000, rec);
    build_rtac_record(1000, RtacEvent::kParityError, 0, Bytes{0x55}, rec);
    w.write_packet(raw, 1000, rec);
    build_rtac_record(2000, RtacEvent::kSerialBreak, 0, {}, rec);  // no byte: flags the next
    w.write_packet(raw, 2000, rec);
    build_rtac_record(3000, RtacEvent::kDataRxStart, 0, Bytes{0x07, 0x08}, rec);
    w.write_packet(raw, 3000, rec);
    build_upper_pdu(Bytes{0x01, 0x07, 0x41, 0xE2}, {}, rec);
    w.write_packet(frames, 4000, rec);
    build_upper_pdu(Bytes{0xFF, 0xFE}, {"data", PduDirection::kUnknown, ""}, rec);
    w.write_packet(frames, 5000, rec);
    build_upper_pdu(Bytes{0x01}, {"mbtcp", PduDirection::kUnknown, ""}, rec);
    w.write_packet(frames, 6000, rec);
  }
  PcapImporter importer(file.path.string());
  PcapItem item;
  ASSERT_TRUE(importer.next(item));
  EXPECT_EQ(importer.declared_settings()->parity, Parity::kOdd);
  ASSERT_EQ(item.kind, PcapItem::Kind::kChunk);
  EXPECT_EQ(item.chunk.t_end, 1000);
  EXPECT_EQ(Bytes(item.chunk.bytes.begin(), item.chunk.bytes.end()), (Bytes{0x01, 0x03, 0x55}));
  EXPECT_EQ(Bytes(item.chunk.errors.begin(), item.chunk.errors.end()), (Bytes{0, 0, kParityError}));
  ASSERT_TRUE(importer.next(item));
  ASSERT_EQ(item.kind, PcapItem::Kind::kChunk);
  EXPECT_EQ(item.chunk.t_end, 3000);
  EXPECT_EQ(Bytes(item.chunk.errors.begin(), item.chunk.errors.end()), (Bytes{kBreak, 0}));
  ASSERT_TRUE(importer.next(item));
  EXPECT_EQ(item.kind, PcapItem::Kind::kFrame);
  EXPECT_EQ(item.t_start, 4000);
  EXPECT_EQ(item.bytes.size(), 4U);
  ASSERT_TRUE(importer.next(item));
  EXPECT_EQ(item.kind, PcapItem::Kind::kNoise);
  EXPECT_EQ(Bytes(item.bytes.begin(), item.bytes.end()), (Bytes{0xFF, 0xFE}));
  try {
    importer.next(item);
    FAIL() << "expected InputError for dissector mbtcp";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("offset "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("dissector 'mbtcp'"), std::string::npos) << e.what();
  }
}

TEST(PcapExport, CommentsNameIssuesAndWhatWiresharkWillNotDecode) {
  Record r;
  r.size = 4;
  r.storage = {0x01, 0x07, 0x41, 0xE2};
  EXPECT_EQ(export_comment(r), "4-byte frame: Wireshark's Modbus RTU dissector needs at least 5");
  r.size = 8;
  r.storage[0] = 0x00;
  r.issues.add(IssueId::kCrc);
  r.issues.add(IssueId::kT35);
  EXPECT_EQ(export_comment(r),
            "broadcast (unit 0): Wireshark's Modbus RTU dissector does not decode it; crc: CRC "
            "check failed; t3.5: less than t3.5 of silence before the frame");
  r.storage[0] = 0x01;
  r.issues = IssueSet{};
  EXPECT_EQ(export_comment(r), "");
}

}  // namespace
}  // namespace rtu
