#include "capture/open_capture.hpp"

#include <gtest/gtest.h>

#include <string>

#include "capture/saleae_reader.hpp"
#include "capture/text_hex_reader.hpp"
#include "capture_test_files.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

using testing::read_all;
using testing::TempDir;

std::string error_of(const std::string& path) {
  try {
    auto source = open_capture(path);
    read_all(*source);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

constexpr std::string_view kLegacy = "Time [s],Value,Parity Error,Framing Error\n0.5,0x01,,\n";
constexpr std::string_view kTable =
    "name,type,start_time,duration,\"data\"\na,data,0.5,0.001,0x01\n";

TEST(OpenCapture, ContentWinsOverTheExtension) {
  TempDir dir;
  const auto hex_as_csv = dir.write("looks.csv", "0.5 01 02\n");
  const auto legacy_as_txt = dir.write("looks.txt", kLegacy);
  const auto table_as_hex = dir.write("looks.hex", kTable);
  EXPECT_EQ(detect_capture_format(hex_as_csv), CaptureFormat::kTextHex);
  EXPECT_EQ(detect_capture_format(legacy_as_txt), CaptureFormat::kSaleaeCsv);
  EXPECT_EQ(detect_capture_format(table_as_hex), CaptureFormat::kSaleaeCsv);

  auto text = open_capture(hex_as_csv);
  EXPECT_NE(dynamic_cast<TextHexReader*>(text.get()), nullptr);
  EXPECT_EQ(read_all(*text).at(0).bytes, (std::vector<std::uint8_t>{0x01, 0x02}));
  EXPECT_EQ(text->name(), hex_as_csv);

  auto legacy = open_capture(legacy_as_txt);
  auto* legacy_reader = dynamic_cast<SaleaeReader*>(legacy.get());
  ASSERT_NE(legacy_reader, nullptr);
  EXPECT_EQ(legacy_reader->layout(), SaleaeLayout::kLegacy);

  auto table = open_capture(table_as_hex);
  auto* table_reader = dynamic_cast<SaleaeReader*>(table.get());
  ASSERT_NE(table_reader, nullptr);
  EXPECT_EQ(table_reader->layout(), SaleaeLayout::kDataTable);
  EXPECT_EQ(read_all(*table).at(0).t_end, 501'000'000);
}

TEST(OpenCapture, TextCapturesStartingWithCommentsOrBlankLinesAreText) {
  TempDir dir;
  EXPECT_EQ(detect_capture_format(dir.write("a.dat", "\n\n# baud=19200\n0.1 01\n")),
            CaptureFormat::kTextHex);
  EXPECT_EQ(detect_capture_format(dir.write("b.csv", "  -1.5 01\n")), CaptureFormat::kTextHex);
}

TEST(OpenCapture, UnrecognisedContentFallsBackToTheExtension) {
  TempDir dir;
  const auto csv = dir.write("odd.csv", "Time,Channel 0\n0.1,1\n");
  const auto txt = dir.write("odd.txt", "hello\n");
  const auto pcap = dir.write("odd.pcap", "");
  EXPECT_EQ(detect_capture_format(csv), CaptureFormat::kSaleaeCsv);
  EXPECT_EQ(detect_capture_format(txt), CaptureFormat::kTextHex);
  EXPECT_EQ(detect_capture_format(pcap), CaptureFormat::kPcap);
  // The chosen reader then says what it expected.
  EXPECT_EQ(error_of(csv).rfind(csv + ":1:1: expected a Saleae Logic export header", 0), 0U)
      << error_of(csv);
  EXPECT_EQ(error_of(txt), txt +
                               ":1:1: expected a timestamp in decimal seconds (like 12.345678), "
                               "found 'hello'");
}

TEST(OpenCapture, PcapAndPcapngMagicAreRecognisedWhateverTheName) {
  TempDir dir;
  const auto pcap =
      dir.write("capture.hex", std::string_view("\xD4\xC3\xB2\xA1\x02\x00\x04\x00", 8));
  const auto pcap_ns_be = dir.write("b.bin", std::string_view("\xA1\xB2\x3C\x4D", 4));
  const auto pcapng =
      dir.write("capture.csv", std::string_view("\x0A\x0D\x0D\x0A\x1C\x00\x00\x00", 8));
  EXPECT_EQ(detect_capture_format(pcap), CaptureFormat::kPcap);
  EXPECT_EQ(detect_capture_format(pcap_ns_be), CaptureFormat::kPcap);
  EXPECT_EQ(detect_capture_format(pcapng), CaptureFormat::kPcap);
  // The pcap reader then says where the (8-byte) file ends.
  EXPECT_EQ(error_of(pcap), pcap + ": offset 8: pcap global header cut off after 8 of 24 bytes");
}

TEST(OpenCapture, MissingOrUnreadableFileNamesThePathAndTheReason) {
  TempDir dir;
  const std::string missing = (dir.path() / "missing.hex").string();
  EXPECT_EQ(error_of(missing), missing + ": cannot open: No such file or directory");
  const std::string folder = dir.path().string();
  EXPECT_EQ(error_of(folder), folder + ": cannot read: Is a directory");
}

TEST(OpenCapture, CompressedAndUtf16FilesAreNamedForWhatTheyAre) {
  TempDir dir;
  const std::string tail = "; expected a text hex capture or a Saleae Logic CSV export";
  const auto gz = dir.write("c.hex.gz", std::string_view("\x1F\x8B\x08\x00", 4));
  const auto zst = dir.write("c.hex.zst", std::string_view("\x28\xB5\x2F\xFD", 4));
  const auto utf16 = dir.write("c.hex", std::string_view("\xFF\xFE"
                                                         "0\0.\0"
                                                         "1\0 \0",
                                                         10));
  const auto utf16_no_bom = dir.write("d.hex", std::string_view("0\0.\0"
                                                                "1\0 \0",
                                                                8));
  EXPECT_EQ(error_of(gz), gz + ": the file is gzip-compressed; decompress it first (zcat)" + tail);
  EXPECT_EQ(error_of(zst),
            zst + ": the file is zstd-compressed; decompress it first (zstdcat)" + tail);
  EXPECT_EQ(error_of(utf16), utf16 + ": the file is UTF-16 text; save it as ASCII or UTF-8" + tail);
  EXPECT_EQ(error_of(utf16_no_bom),
            utf16_no_bom + ": the file is UTF-16 text; save it as ASCII or UTF-8" + tail);
}

TEST(OpenCapture, Utf8ByteOrderMarkIsIgnored) {
  TempDir dir;
  const auto text = dir.write("bom.txt", "\xEF\xBB\xBF# baud=19200\n0.5 01\n");
  EXPECT_EQ(detect_capture_format(text), CaptureFormat::kTextHex);
  auto source = open_capture(text);
  EXPECT_EQ(read_all(*source).size(), 1U);
  ASSERT_TRUE(source->declared_settings().has_value());
  EXPECT_EQ(source->declared_settings()->baud, 19200U);
  const auto legacy =
      dir.write("bom.csv", "\xEF\xBB\xBFTime [s],Value,Parity Error,Framing Error\n0.5,0x01,,\n");
  EXPECT_EQ(detect_capture_format(legacy), CaptureFormat::kSaleaeCsv);
  auto saleae = open_capture(legacy);
  EXPECT_EQ(read_all(*saleae).size(), 1U);
}

TEST(OpenCapture, EmptyFileIsAnEmptyTextCapture) {
  TempDir dir;
  const auto empty = dir.write("empty.hex", "");
  auto source = open_capture(empty);
  EXPECT_TRUE(read_all(*source).empty());
  EXPECT_EQ(source->timestamp_precision(), 0);
}

}  // namespace
}  // namespace rtu
