// The format registries: the names the command line accepts, extension lookups, and that each
// entry makes what it names. The command line's choices and help texts come from here, so
// these values are a public interface.
#include "core/format_registry.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capture/capture_formats.hpp"
#include "capture/pcap_capture_reader.hpp"
#include "capture/saleae_reader.hpp"
#include "capture/text_hex_reader.hpp"
#include "capture_test_files.hpp"
#include "report/export_formats.hpp"
#include "report/jsonl_writer.hpp"
#include "report/record_formats.hpp"
#include "report/report_formats.hpp"
#include "report/text_writer.hpp"

namespace rtu {
namespace {

using Names = std::vector<std::string>;

TEST(FormatRegistry, CommandLineChoicesAreTheRegisteredNamesInOrder) {
  EXPECT_EQ(format_names(record_formats()), (Names{"text", "jsonl"}));
  EXPECT_EQ(format_names(report_formats()), (Names{"text", "json", "html"}));
  EXPECT_EQ(format_names(export_formats()), (Names{"pcapng", "pcap"}));
  EXPECT_EQ(format_names(capture_formats()), (Names{"hex", "saleae", "pcap"}));
}

TEST(FormatRegistry, HelpTextsAreGeneratedFromTheRegistry) {
  EXPECT_EQ(capture_file_help(), "Capture: text hex (.hex/.txt), Saleae CSV, pcap/pcapng");
  EXPECT_EQ(export_output_help(), "Output file: .pcapng or .pcap");
}

TEST(FormatRegistry, UnknownNamesAreNotFound) {
  EXPECT_EQ(find_format(record_formats(), "json"), nullptr);
  EXPECT_EQ(find_format(record_formats(), "JSONL"), nullptr);
  EXPECT_EQ(find_format(report_formats(), "jsonl"), nullptr);
  EXPECT_EQ(find_format(report_formats(), ""), nullptr);
  const auto* html = find_format(report_formats(), "html");
  ASSERT_NE(html, nullptr);
  EXPECT_EQ(html->name, "html");
  // Dispatchers fall back to the default, the first entry.
  EXPECT_EQ(find_format_or_default(report_formats(), "pdf").name, "text");
  EXPECT_EQ(find_format_or_default(report_formats(), "json").name, "json");
  EXPECT_EQ(find_format_or_default(record_formats(), "jsonl").name, "jsonl");
}

TEST(FormatRegistry, ReportAndExportExtensionsMatchAsWrittenWithADefault) {
  EXPECT_EQ(report_format_for_path("out/report.html").name, "html");
  EXPECT_EQ(report_format_for_path("report.htm").name, "html");
  EXPECT_EQ(report_format_for_path("report.json").name, "json");
  EXPECT_EQ(report_format_for_path("report.txt").name, "text");
  EXPECT_EQ(report_format_for_path("report.HTML").name, "text");  // case as written
  EXPECT_EQ(report_format_for_path("html").name, "text");         // a suffix, not a name
  EXPECT_EQ(export_format_for_path("frames.pcap").factory, PcapExportFormat::kPcap);
  EXPECT_EQ(export_format_for_path("frames.pcapng").factory, PcapExportFormat::kPcapng);
  EXPECT_EQ(export_format_for_path("frames.bin").factory, PcapExportFormat::kPcapng);
  EXPECT_EQ(export_format_for_path("frames.PCAP").factory, PcapExportFormat::kPcapng);
}

TEST(FormatRegistry, CaptureExtensionsMatchWhateverTheCase) {
  const auto format_of = [](const std::string& path) {
    const auto* entry = capture_format_for_path(path);
    return entry == nullptr ? std::string("none") : std::string(entry->name);
  };
  EXPECT_EQ(format_of("a.PCAPNG"), "pcap");
  EXPECT_EQ(format_of("a.cap"), "pcap");
  EXPECT_EQ(format_of("a.Csv"), "saleae");
  EXPECT_EQ(format_of("a.hex"), "hex");
  EXPECT_EQ(format_of("a.dat"), "none");
  EXPECT_EQ(capture_format(CaptureFormat::kSaleaeCsv).name, "saleae");
  EXPECT_EQ(capture_format(CaptureFormat::kPcap).name, "pcap");
}

TEST(FormatRegistry, EachCaptureFormatOpensItsReader) {
  testing::TempDir dir;
  const auto hex = dir.write("a.hex", "0.5 01 02\n");
  const auto csv = dir.write("a.csv", "Time [s],Value,Parity Error,Framing Error\n0.5,0x01,,\n");
  const auto pcap = dir.write("a.pcap", std::string_view("\xD4\xC3\xB2\xA1\x02\x00\x04\x00"
                                                         "\0\0\0\0\0\0\0\0\xFF\xFF\0\0\xFC\0\0\0",
                                                         24));
  const auto quiet = [](std::string_view) {};
  auto text = capture_format(CaptureFormat::kTextHex).factory.open(hex, quiet);
  EXPECT_NE(dynamic_cast<TextHexReader*>(text.get()), nullptr);
  auto saleae = capture_format(CaptureFormat::kSaleaeCsv).factory.open(csv, quiet);
  EXPECT_NE(dynamic_cast<SaleaeReader*>(saleae.get()), nullptr);
  auto pcap_reader = capture_format(CaptureFormat::kPcap).factory.open(pcap, quiet);
  EXPECT_NE(dynamic_cast<PcapCaptureReader*>(pcap_reader.get()), nullptr);
  EXPECT_TRUE(pcap_reader->holds_frames());
  EXPECT_FALSE(text->holds_frames());
}

TEST(FormatRegistry, EachRecordFormatMakesItsWriter) {
  OutputStream out("-");
  const auto* text = find_format(record_formats(), "text");
  const auto* jsonl = find_format(record_formats(), "jsonl");
  ASSERT_NE(text, nullptr);
  ASSERT_NE(jsonl, nullptr);
  const auto text_writer = text->factory(out);
  const auto jsonl_writer = jsonl->factory(out);
  EXPECT_NE(dynamic_cast<TextWriter*>(text_writer.get()), nullptr);
  EXPECT_NE(dynamic_cast<JsonlWriter*>(jsonl_writer.get()), nullptr);
}

}  // namespace
}  // namespace rtu
