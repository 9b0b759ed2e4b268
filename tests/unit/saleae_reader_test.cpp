#include "capture/saleae_reader.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capture_test_files.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

using testing::read_all;
using testing::TempDir;

using Bytes = std::vector<std::uint8_t>;

std::string error_of(const std::string& path) {
  try {
    SaleaeReader reader(path);
    read_all(reader);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SaleaeReader, LegacyLayoutGivesOneExactlyTimedByteAChunkWithErrorFlags) {
  TempDir dir;
  const auto path = dir.write("legacy.csv",
                              "Time [s],Value,Parity Error,Framing Error\n"
                              "-0.000104166666667,0x01,,\n"
                              "0.000000000000000,0x03,Error,\n"
                              "0.042909760000000,0x00,,Error\n"
                              "0.043000000000000,0xFF,Error,Error\n");
  SaleaeReader reader(path);
  EXPECT_EQ(reader.layout(), SaleaeLayout::kLegacy);
  EXPECT_EQ(reader.timing_kind(), TimingKind::kPerByteExact);
  EXPECT_EQ(reader.declared_settings(), std::nullopt);
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 4U);
  EXPECT_EQ(chunks[0].t_first_start, -104'167);  // 15 decimals, rounded to the ns
  EXPECT_EQ(chunks[2].t_first_start, 42'909'760);
  const std::vector<std::uint8_t> flags = {kLineOk, kParityError, kFramingError,
                                           kParityError | kFramingError};
  const Bytes values = {0x01, 0x03, 0x00, 0xFF};
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    EXPECT_EQ(chunks[i].t_end, chunks[i].t_first_start) << "legacy has no duration";
    EXPECT_EQ(chunks[i].bytes, Bytes{values[i]});
    EXPECT_EQ(chunks[i].errors, Bytes{flags[i]});
    EXPECT_EQ(chunks[i].origin, i + 2);
  }
  EXPECT_EQ(reader.timestamp_precision(), 1);
}

TEST(SaleaeReader, DataTableLayoutWithDurationsAndENotation) {
  TempDir dir;
  // The first row is from a real Logic 2 export.
  const auto path = dir.write("table.csv",
                              "name,type,start_time,duration,\"data\",\"error\"\r\n"
                              "\"Async 1\",\"data\",0.000592672,8.2464e-05,0x31,\r\n"
                              "\"Async 1\",\"data\",1.5E-3,0.001145833,0x0a,\"parity\"\r\n"
                              "\"Async, 2\",\"data\",2e-3,1.1e-3,0xA5,framing\r\n");
  SaleaeReader reader(path);
  EXPECT_EQ(reader.layout(), SaleaeLayout::kDataTable);
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 3U);
  EXPECT_EQ(chunks[0].t_first_start, 592'672);
  EXPECT_EQ(chunks[0].t_end, 592'672 + 82'464);
  EXPECT_EQ(chunks[0].bytes, Bytes{0x31});
  EXPECT_EQ(chunks[0].errors, Bytes{kLineOk});
  EXPECT_EQ(chunks[1].t_first_start, 1'500'000);
  EXPECT_EQ(chunks[1].t_end, 1'500'000 + 1'145'833);
  EXPECT_EQ(chunks[1].bytes, Bytes{0x0A});
  EXPECT_EQ(chunks[1].errors, Bytes{kParityError});
  EXPECT_EQ(chunks[2].t_first_start, 2'000'000);  // a second analyzer is merged in file order
  EXPECT_EQ(chunks[2].t_end, 3'100'000);
  EXPECT_EQ(chunks[2].errors, Bytes{kFramingError});
  EXPECT_EQ(reader.timestamp_precision(), 1);  // 8.2464e-05 has 9 decimals
}

TEST(SaleaeReader, DataTableColumnsAreFoundByNameAndErrorColumnIsOptional) {
  TempDir dir;
  const auto path = dir.write("table.csv",
                              "\xEF\xBB\xBF\"data\",duration,start_time,type,name,\"extra\"\n"
                              "0x10,0.001,1.25,data,Async Serial,whatever\n");
  SaleaeReader reader(path);
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 1U);
  EXPECT_EQ(chunks[0].bytes, Bytes{0x10});
  EXPECT_EQ(chunks[0].t_first_start, 1'250'000'000);
  EXPECT_EQ(chunks[0].t_end, 1'251'000'000);
  EXPECT_EQ(chunks[0].errors, Bytes{kLineOk});
  EXPECT_EQ(reader.timestamp_precision(), 10 * kNanosPerMilli);  // "1.25": 2 decimals
}

TEST(SaleaeReader, DataTableIso8601TimesAreNanosecondsSinceTheUnixEpoch) {
  TempDir dir;
  const auto path =
      dir.write("iso.csv",
                "name,type,start_time,duration,\"data\"\n"
                "\"Async 1\",\"data\",2022-06-29T04:05:27.591152100+00:00,8.2464e-05,0x31\n"
                "\"Async 1\",\"data\",2022-06-29T06:05:28.5+02:00,8.2464e-05,0x32\n"
                "\"Async 1\",\"data\",2024-02-29T12:00:00Z,8.2464e-05,0x33\n");
  SaleaeReader reader(path);
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 3U);
  EXPECT_EQ(chunks[0].t_first_start, 1'656'475'527'591'152'100);
  EXPECT_EQ(chunks[0].t_end, 1'656'475'527'591'152'100 + 82'464);
  EXPECT_EQ(chunks[1].t_first_start, 1'656'475'528'500'000'000);        // +02:00 taken off
  EXPECT_EQ(chunks[2].t_first_start, 1'709'208'000 * kNanosPerSecond);  // a leap day
}

TEST(SaleaeReader, BackwardStartIsClampedKeepingTheDuration) {
  TempDir dir;
  const auto path = dir.write("back.csv",
                              "name,type,start_time,duration,\"data\"\n"
                              "a,data,0.002,0.001,0x01\n"
                              "a,data,0.001,0.001,0x02\n");
  std::vector<std::string> warnings;
  SaleaeReader reader(path, [&](std::string_view m) { warnings.emplace_back(m); });
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 2U);
  EXPECT_EQ(chunks[1].t_first_start, 2'000'000);
  EXPECT_EQ(chunks[1].t_end, 3'000'000);
  EXPECT_FALSE(chunks[0].time_clamped);
  EXPECT_TRUE(chunks[1].time_clamped);
  ASSERT_EQ(warnings.size(), 1U);
  EXPECT_EQ(warnings[0],
            path + ":3: timestamp goes backwards (0.001 after 0.002 on line 2); using 0.002");
}

TEST(SaleaeReader, ErrorsSayFileLineColumnAndWhatWasExpected) {
  TempDir dir;
  const std::string legacy = "Time [s],Value,Parity Error,Framing Error\n";
  const std::string table = "name,type,start_time,duration,\"data\",\"error\"\n";
  const std::string radix =
      "a byte in the hex radix like 0x55 (export the analyzer with the hex display radix; "
      "decimal, ASCII and binary values are not accepted)";
  const std::string header_expected =
      "expected a Saleae Logic export header ('Time [s],Value,Parity Error,Framing Error' or "
      "'name,type,start_time,duration,\"data\"'), found ";
  const std::string mp =
      "1:1: the multi-processor (MP/MDB) mode of the Async Serial analyzer is not supported; "
      "expected an export of the analyzer in its normal mode (Modbus RTU uses 8 data bits, no "
      "address bit)";
  struct Case {
    std::string content;
    std::string message;  // after "PATH:"
  };
  const std::vector<Case> cases = {
      {legacy + "0.1,85,,\n", "2:5: expected " + radix + " in column 'Value', found '85'"},
      {legacy + "0.1,U,,\n", "2:5: expected " + radix + " in column 'Value', found 'U'"},
      {legacy + "0.1,0x,,\n", "2:5: expected " + radix + " in column 'Value', found '0x'"},
      {legacy + "0.1,0x55,Oops,\n",
       "2:10: expected 'Error' or nothing in column 'Parity Error', found 'Oops'"},
      {legacy + "zero,0x55,,\n",
       "2:1: expected a time in seconds (like 0.042909760000000) in column 'Time [s]', found "
       "'zero'"},
      {legacy + "0.1\n", "2:4: expected " + radix + " in column 'Value', found end of line"},
      {"Time [s],Packet ID,Address,Data,Framing Error\n", mp},
      {"name,type,start_time,duration,\"data\",\"address\"\n", mp},
      {"Time,Channel 0\n0.1,1\n", "1:1: " + header_expected + "'Time,Channel 0'"},
      {"", "1: " + header_expected.substr(0, header_expected.size() - 6) + "found an empty file"},
      {"name,type,start_time,\"data\"\n",
       "1:1: expected a 'duration' column in the data table header"},
      {"name,type,start_time,duration\n",
       "1:1: expected a 'data' column in the data table header (export an Async Serial "
       "analyzer)"},
      {table + "a,data,0.1,0.001,0x486900,\n",
       "2:18: expected one byte per row like 0x55, not 6 hex digits in column 'data', found "
       "'0x486900'"},
      {table + "a,start,0.1,0.001,0x48,\n",
       "2:3: expected 'data' (rows of an Async Serial analyzer) in column 'type', found 'start'"},
      {table + "a,data,0.1,0.001,0x48,overrun\n",
       "2:23: expected 'parity', 'framing' or nothing in column 'error', found 'overrun'"},
      {table + "a,data,0.1,-0.001,0x48,\n",
       "2:12: expected a duration of zero or more seconds in column 'duration', found '-0.001'"},
      {table + "a,data,yesterday,0.001,0x48,\n",
       "2:8: expected a time in seconds (like 0.000592672 or 8.2464e-05) or ISO 8601 in column "
       "'start_time', found 'yesterday'"},
      {table + "a,data,2022-02-30T00:00:00Z,0.001,0x48,\n",
       "2:8: expected a time in seconds (like 0.000592672 or 8.2464e-05) or ISO 8601 in column "
       "'start_time', found '2022-02-30T00:00:00Z'"},
      {table + "a,data,1e300,0.001,0x48,\n",
       "2:8: expected a time within 292 years of the epoch in column 'start_time', found "
       "'1e300'"},
      {table + "\"a,data,0.1,0.001,0x48,\n",
       "2:1: expected a CSV field with closed quotes followed by ',' or the end of the line"},
  };
  for (const auto& c : cases) {
    const auto path = dir.write("bad.csv", c.content);
    EXPECT_EQ(error_of(path), path + ":" + c.message) << c.content;
  }
}

TEST(SaleaeReader, HundredThousandRowsStreamWithFlatMemory) {
  TempDir dir;
  constexpr int kRows = 100'000;
  std::string content = "name,type,start_time,duration,\"data\",\"error\"\n";
  char row[128];
  for (int i = 0; i < kRows; ++i) {
    const int len =
        std::snprintf(row, sizeof row, "\"Async Serial\",\"data\",%d.%06d,0.001145,0x%02X,%s\n",
                      i / 1000, (i % 1000) * 1000, i % 256, i % 100 == 0 ? "parity" : "");
    content.append(row, static_cast<std::size_t>(len));
  }
  const auto path = dir.write("big.csv", content);
  SaleaeReader reader(path);
  Chunk chunk;
  std::uint64_t rows = 0;
  std::uint64_t byte_sum = 0;
  std::uint64_t parity = 0;
  testing::AllocationCounter counter;
  while (reader.next(chunk)) {
    if (rows == 100) counter.start();
    ++rows;
    byte_sum += chunk.bytes[0];
    parity += (chunk.errors[0] & kParityError) != 0 ? 1U : 0U;
  }
  const std::uint64_t allocations = counter.count();
  EXPECT_EQ(rows, static_cast<std::uint64_t>(kRows));
  EXPECT_EQ(byte_sum, (kRows / 256) * (255 * 256 / 2) + (kRows % 256) * (kRows % 256 - 1) / 2);
  EXPECT_EQ(parity, static_cast<std::uint64_t>(kRows / 100));
  if (testing::AllocationCounter::available()) {
    EXPECT_EQ(allocations, 0U) << "reading allocated after warm-up";
  }
}

}  // namespace
}  // namespace rtu
