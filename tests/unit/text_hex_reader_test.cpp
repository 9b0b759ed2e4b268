#include "capture/text_hex_reader.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "capture_test_files.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

using testing::CopiedChunk;
using testing::read_all;
using testing::TempDir;

using Bytes = std::vector<std::uint8_t>;

// The message of the InputError that reading all of `path` throws ("" when none).
std::string error_of(const std::string& path) {
  try {
    TextHexReader reader(path);
    read_all(reader);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TextHexReader, TimestampsAreExactToTheNanosecond) {
  TempDir dir;
  const auto path = dir.write("t.hex",
                              "1700000000.123456789 01\n"
                              "1700000000.9999999994 02\n"  // rounds down
                              "1700000000.9999999995 03\n"  // rounds up, carrying into seconds
                              "1700000001.5 04\n"
                              "1700000002 05\n");
  TextHexReader reader(path);
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 5U);
  EXPECT_EQ(chunks[0].t_end, 1'700'000'000'123'456'789);
  EXPECT_EQ(chunks[1].t_end, 1'700'000'000'999'999'999);
  EXPECT_EQ(chunks[2].t_end, 1'700'000'001'000'000'000);
  EXPECT_EQ(chunks[3].t_end, 1'700'000'001'500'000'000);
  EXPECT_EQ(chunks[4].t_end, 1'700'000'002'000'000'000);
  for (const auto& c : chunks) EXPECT_EQ(c.t_first_start, kUnknownTime);
  EXPECT_EQ(reader.timing_kind(), TimingKind::kReadCompletion);
}

TEST(TextHexReader, NegativeAndFractionOnlyTimes) {
  TempDir dir;
  const auto path = dir.write("t.hex",
                              "-2.5 01\n"
                              "-0.0000000005 02\n"  // half a nanosecond rounds away from zero
                              ".25 03\n"
                              "+1.000001 04\n");
  TextHexReader reader(path);
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 4U);
  EXPECT_EQ(chunks[0].t_end, -2'500'000'000);
  EXPECT_EQ(chunks[1].t_end, -1);
  EXPECT_EQ(chunks[2].t_end, 250'000'000);
  EXPECT_EQ(chunks[3].t_end, 1'000'001'000);
}

TEST(TextHexReader, BothHexSpellingsGiveTheSameBytes) {
  TempDir dir;
  const auto path = dir.write("t.hex",
                              "1.0 01 03 00 0a 00 03 25 C9\n"
                              "2.0 0103000A000325c9\n"
                              "3.0\t01 0300\t0A00 0325C9\n");
  TextHexReader reader(path);
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 3U);
  const Bytes expected = {0x01, 0x03, 0x00, 0x0A, 0x00, 0x03, 0x25, 0xC9};
  for (const auto& c : chunks) {
    EXPECT_EQ(c.bytes, expected);
    EXPECT_TRUE(c.errors.empty());
  }
}

TEST(TextHexReader, CommentsBlankLinesAndCrLfAreSkippedAndOriginIsTheLineNumber) {
  TempDir dir;
  const auto path = dir.write("t.hex",
                              "# a capture\r\n"
                              "\r\n"
                              "   # indented comment\n"
                              "0.001 01 02 # trailing comment\r\n"
                              "\t \n"
                              "  0.002 03\n"
                              "0.003 04");  // no newline at the end
  TextHexReader reader(path);
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 3U);
  EXPECT_EQ(chunks[0].bytes, (Bytes{0x01, 0x02}));
  EXPECT_EQ(chunks[0].origin, 4U);
  EXPECT_EQ(chunks[1].bytes, (Bytes{0x03}));
  EXPECT_EQ(chunks[1].origin, 6U);
  EXPECT_EQ(chunks[2].bytes, (Bytes{0x04}));
  EXPECT_EQ(chunks[2].origin, 7U);
  EXPECT_EQ(reader.declared_settings(), std::nullopt);
}

TEST(TextHexReader, SettingsCommentIsKnownBeforeTheFirstChunk) {
  TempDir dir;
  const auto path = dir.write("t.hex",
                              "# bus A, sniffed at baud=19200 parity=O stop=2 (meter side)\n"
                              "0.1 01\n");
  TextHexReader reader(path);
  const auto settings = reader.declared_settings();
  ASSERT_TRUE(settings.has_value());
  EXPECT_EQ(settings->baud, 19200U);
  EXPECT_EQ(settings->parity, Parity::kOdd);
  EXPECT_EQ(settings->stop_bits, 2U);
}

TEST(TextHexReader, PartialSettingsInAnyOrderAndCaseKeepTheDefaultsForTheRest) {
  TempDir dir;
  const auto path = dir.write("t.hex",
                              "# Parity=none\n"
                              "# BAUD=4800\n"
                              "0.1 01\n"
                              "# baud=4800 parity=N\n"  // repeating them later is fine
                              "0.2 02\n");
  TextHexReader reader(path);
  EXPECT_EQ(read_all(reader).size(), 2U);
  const auto settings = reader.declared_settings();
  ASSERT_TRUE(settings.has_value());
  EXPECT_EQ(settings->baud, 4800U);
  EXPECT_EQ(settings->parity, Parity::kNone);
  EXPECT_EQ(settings->stop_bits, 1U);
}

TEST(TextHexReader, PrecisionIsTheFinestStepWritten) {
  TempDir dir;
  struct Case {
    const char* content;
    Nanos precision;
  };
  const std::vector<Case> cases = {
      {"1.123 01\n", kNanosPerMilli},
      {"1.5 01\n1.52 02\n1.523 03\n1.6 04\n", kNanosPerMilli},  // trailing zeros dropped
      {"1.123456 01\n", kNanosPerMicro},
      {"12 01\n", kNanosPerSecond},
      {"1.123456789012 01\n", 1},
      {"# nothing\n", 0},
  };
  for (const auto& c : cases) {
    const auto path = dir.write("p.hex", c.content);
    TextHexReader reader(path);
    read_all(reader);
    EXPECT_EQ(reader.timestamp_precision(), c.precision) << c.content;
  }
}

TEST(TextHexReader, BackwardTimeIsClampedAndReported) {
  TempDir dir;
  const auto path = dir.write("t.hex", "1.5 01\n1.2 02\n1.6 03\n");
  std::vector<std::string> warnings;
  TextHexReader reader(path, [&](std::string_view m) { warnings.emplace_back(m); });
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 3U);
  EXPECT_EQ(chunks[0].t_end, 1'500'000'000);
  EXPECT_EQ(chunks[1].t_end, 1'500'000'000);
  EXPECT_EQ(chunks[1].bytes, (Bytes{0x02}));  // the bytes are kept
  EXPECT_EQ(chunks[2].t_end, 1'600'000'000);
  // Only the clamped read's time is marked as not the input's.
  EXPECT_FALSE(chunks[0].time_clamped);
  EXPECT_TRUE(chunks[1].time_clamped);
  EXPECT_FALSE(chunks[2].time_clamped);
  ASSERT_EQ(warnings.size(), 1U);
  EXPECT_EQ(warnings[0],
            path + ":2: timestamp goes backwards (1.2 after 1.5 on line 1); using 1.5");
}

// The time in force is quoted as written, however long: stamps of up to 40 characters are
// kept one way, longer ones another, and a short one after a long one must not show the
// long one's tail.
TEST(TextHexReader, BackwardTimeQuotesTheTimeInForceAsWrittenWhateverItsLength) {
  TempDir dir;
  const std::string long_stamp = "1.5000000000000000000000000000000000000000000000";  // 48
  const auto path = dir.write("t.hex", long_stamp + " 01\n1.2 02\n1.7 03\n1.6 04\n");
  std::vector<std::string> warnings;
  TextHexReader reader(path, [&](std::string_view m) { warnings.emplace_back(m); });
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 4U);
  ASSERT_EQ(warnings.size(), 2U);
  EXPECT_EQ(warnings[0], path + ":2: timestamp goes backwards (1.2 after " + long_stamp +
                             " on line 1); using " + long_stamp);
  EXPECT_EQ(warnings[1],
            path + ":4: timestamp goes backwards (1.6 after 1.7 on line 3); using 1.7");
}

// The time in force is quoted from where the reader read it, not copied at every line: it
// must still be quoted right when the line reader has refilled its buffer since (the line
// in force at the end of one buffer, across two, the line going back in the next), and
// when a comment was read between the two lines.
TEST(TextHexReader, BackwardTimeQuotesTheTimeInForceAcrossTheReadersBuffers) {
  TempDir dir;
  const std::size_t filler_lines = 65536 / 7 - 3;  // "0.1 00\n" up to near the first refill
  for (const bool comment_between : {false, true}) {
    for (std::size_t pad = 0; pad < 40; ++pad) {
      std::string content = "#" + std::string(pad, 'x') + "\n";
      for (std::size_t i = 0; i < filler_lines; ++i) content += "0.1 00\n";
      content += "5.123456789 01\n";
      if (comment_between) content += "# a note\n";
      content += "1.0 02\n";
      const auto path = dir.write("t.hex", content);
      std::vector<std::string> warnings;
      TextHexReader reader(path, [&](std::string_view m) { warnings.emplace_back(m); });
      const auto chunks = read_all(reader);
      ASSERT_EQ(chunks.size(), filler_lines + 2);
      EXPECT_EQ(chunks.back().t_end, 5'123'456'789);
      const std::size_t in_force = filler_lines + 2;
      const std::size_t back = in_force + (comment_between ? 2 : 1);
      ASSERT_EQ(warnings.size(), 1U) << pad;
      EXPECT_EQ(warnings[0], fmt::format("{}:{}: timestamp goes backwards (1.0 after 5.123456789 "
                                         "on line {}); using 5.123456789",
                                         path, back, in_force))
          << "pad " << pad << (comment_between ? ", comment between" : "");
    }
  }
}

TEST(TextHexReader, ManyBackwardTimesAreSummarisedAtTheEnd) {
  TempDir dir;
  std::string content = "9.0 00\n";
  for (int i = 0; i < 8; ++i) content += "1.0 01\n";
  const auto path = dir.write("t.hex", content);
  std::vector<std::string> warnings;
  TextHexReader reader(path, [&](std::string_view m) { warnings.emplace_back(m); });
  const auto chunks = read_all(reader);
  EXPECT_EQ(chunks.size(), 9U);
  for (const auto& c : chunks) EXPECT_EQ(c.t_end, 9 * kNanosPerSecond);
  ASSERT_EQ(warnings.size(), 6U);
  EXPECT_EQ(warnings[4],
            path + ":6: timestamp goes backwards (1.0 after 9.0 on line 1); using 9.0");
  EXPECT_EQ(warnings[5], path + ": 3 more timestamps went backwards and were clamped (8 in all)");
}

TEST(TextHexReader, ErrorsSayFileLineColumnAndWhatWasExpected) {
  TempDir dir;
  struct Case {
    const char* content;
    const char* message;  // after "PATH:"
  };
  const std::vector<Case> cases = {
      {"0.1 01 0G\n", "1:8: expected hex byte pair, found '0G'"},
      {"0.1 01 0\n", "1:8: expected hex byte pair, found '0'"},
      {"0.1 0103A\n", "1:9: expected hex byte pair, found 'A'"},
      {"0.1 01 0x02\n", "1:8: expected hex byte pair, found '0x02'"},
      {"# ok\n\n  0.1 01 02 zz\n", "3:13: expected hex byte pair, found 'zz'"},
      {"abc 01\n", "1:1: expected a timestamp in decimal seconds (like 12.345678), found 'abc'"},
      {"1.2.3 01\n",
       "1:1: expected a timestamp in decimal seconds (like 12.345678), found '1.2.3'"},
      {"1e3 01\n", "1:1: expected a timestamp in decimal seconds (like 12.345678), found '1e3'"},
      {"\x01\x02 01\n",
       "1:1: expected a timestamp in decimal seconds (like 12.345678), found '\\x01\\x02'"},
      {"0.1\n", "1:4: expected hex bytes after the timestamp, found end of line"},
      {"0.1    \n", "1:8: expected hex bytes after the timestamp, found end of line"},
      {"99999999999 01\n",
       "1:1: timestamp out of range (more than 292 years from the epoch), found '99999999999'"},
      {"# baud=fast\n",
       "1:8: expected a baud rate (a whole number from 1 to 100000000), found 'fast'"},
      {"# baud=0\n", "1:8: expected a baud rate (a whole number from 1 to 100000000), found '0'"},
      {"# parity=X\n", "1:10: expected parity N, E or O, found 'X'"},
      {"# stop=3\n", "1:8: expected stop bits 1 or 2, found '3'"},
      {"# stop=\n", "1:8: expected stop bits 1 or 2, found end of line"},
      {"0.1 01\n# baud=19200\n",
       "2:3: line settings must come before the first data line; 'baud=19200' changes them"},
  };
  for (const auto& c : cases) {
    const auto path = dir.write("bad.hex", c.content);
    EXPECT_EQ(error_of(path), path + ":" + c.message) << c.content;
  }
}

TEST(TextHexReader, MissingFileSaysWhichAndWhy) {
  const std::string path = "/nonexistent-dir/capture.hex";
  EXPECT_EQ(error_of(path), path + ": cannot open: No such file or directory");
}

TEST(TextHexReader, VeryLongLinesAreReadWhole) {
  TempDir dir;
  // 100 000 bytes on one line: the line straddles several buffer fills.
  std::string content = "# long\n0.5";
  for (int i = 0; i < 100'000; ++i) content += i % 2 == 0 ? " a5" : " 5A";
  content += "\n0.6 01\n";
  const auto path = dir.write("long.hex", content);
  TextHexReader reader(path);
  const auto chunks = read_all(reader);
  ASSERT_EQ(chunks.size(), 2U);
  ASSERT_EQ(chunks[0].bytes.size(), 100'000U);
  EXPECT_EQ(chunks[0].bytes.front(), 0xA5);
  EXPECT_EQ(chunks[0].bytes.back(), 0x5A);
  EXPECT_EQ(chunks[1].bytes, (Bytes{0x01}));
  EXPECT_EQ(chunks[1].origin, 3U);
}

// Nearly every data line is read in place in the line reader's buffer; a line that starts
// with a blank never is (nor is any line it does not know whole). So the same text with a
// blank before every line must give the same chunks, warnings and precision, whatever the
// shapes of its lines and wherever the buffer's ends cut them, and refuse the same lines.
TEST(TextHexReader, LinesReadInPlaceGiveWhatReadingLineByLineGives) {
  std::mt19937 random(11);
  const auto pick = [&random](unsigned n) { return static_cast<unsigned>(random() % n); };
  const auto digits = [&](unsigned n) {
    std::string d;
    for (unsigned i = 0; i < n; ++i) d += static_cast<char>('0' + pick(10));
    return d;
  };
  const auto blanks = [&] {
    static const char* const kBlanks[] = {" ", " ", " ", "\t", "  ", " \t "};
    return std::string(kBlanks[pick(6)]);
  };
  const auto good_line = [&](std::uint64_t& seconds) -> std::string {
    const unsigned kind = pick(100);
    if (kind < 3) return pick(2) == 0 ? "# a note" : (pick(2) == 0 ? "" : " \t");
    // Mostly in order; now and then a step back, which is clamped and reported.
    seconds = pick(50) == 0 ? seconds - pick(5) : seconds + pick(3);
    std::string stamp = kind < 6 ? digits(1 + pick(9)) : std::to_string(seconds);
    const unsigned decimals = pick(14);  // 10 and more: the general parser's
    if (decimals > 0 || pick(4) == 0) stamp += '.';
    stamp += digits(decimals);
    if (kind < 8) stamp.insert(0, pick(2) == 0 ? "-" : "+");
    std::string line = stamp + blanks();
    const unsigned pairs = pick(400) == 0 ? 3000 + pick(20000) : 1 + pick(8);
    for (unsigned i = 0; i < pairs; ++i) {
      const unsigned byte = pick(256);
      line += pick(2) == 0 ? fmt::format("{:02x}", byte) : fmt::format("{:02X}", byte);
      if (pick(4) != 0) line += blanks();
    }
    if (pick(20) == 0) line += "# trailing";
    if (pick(10) == 0) line += '\r';
    return line;
  };
  const auto both_ways = [](const std::vector<std::string>& lines) {
    std::pair<std::string, std::string> texts;
    for (const std::string& line : lines) {
      texts.first += line + '\n';
      texts.second += ' ' + line + '\n';
    }
    texts.first.pop_back();  // the last line without its '\n'
    texts.second.pop_back();
    return texts;
  };
  struct Reading {
    std::vector<testing::CopiedChunk> chunks;
    std::vector<std::string> warnings;
    Nanos precision = 0;
    std::string error;  // without its column, which the blank moves
  };
  TempDir dir;
  const auto read = [&dir](const std::string& content) {
    Reading r;
    const auto path = dir.write("t.hex", content);
    try {
      TextHexReader reader(path, [&r](std::string_view m) { r.warnings.emplace_back(m); });
      r.chunks = read_all(reader);
      r.precision = reader.timestamp_precision();
    } catch (const InputError& e) {
      const std::string message = e.what();  // FILE:LINE:COLUMN: what
      const auto line_end = message.find(':', path.size() + 1);
      r.error = message.substr(0, line_end) + message.substr(message.find(':', line_end + 1));
    }
    return r;
  };
  const auto expect_same = [&](const std::vector<std::string>& lines) {
    const auto [in_place, line_by_line] = both_ways(lines);
    const Reading a = read(in_place);
    const Reading b = read(line_by_line);
    EXPECT_EQ(a.error, b.error);
    EXPECT_EQ(a.chunks.size(), b.chunks.size());
    for (std::size_t i = 0; i < std::min(a.chunks.size(), b.chunks.size()); ++i) {
      const bool same = a.chunks[i].t_end == b.chunks[i].t_end &&
                        a.chunks[i].bytes == b.chunks[i].bytes &&
                        a.chunks[i].origin == b.chunks[i].origin;
      if (!same) {
        ADD_FAILURE() << "chunk " << i << " differs, line " << a.chunks[i].origin << " / "
                      << b.chunks[i].origin;
        break;
      }
    }
    EXPECT_EQ(a.warnings, b.warnings);
    EXPECT_EQ(a.precision, b.precision);
    return a;
  };

  std::uint64_t seconds = 1000;
  std::vector<std::string> lines;
  for (int n = 0; n < 30000; ++n) lines.push_back(good_line(seconds));
  const Reading all = expect_same(lines);
  EXPECT_EQ(all.error, "");
  EXPECT_GT(all.chunks.size(), 25000U);
  EXPECT_GT(all.warnings.size(), 5U);

  // Each refused line after good ones (each time a different stretch of the buffer).
  const char* const kRefused[] = {"1e3 01",
                                  "1.5 0G",
                                  "1.5",
                                  "1.5#c 01",
                                  "1.5 012",
                                  "1.5 01 0",
                                  "1.5 01 0x",
                                  "1.5x 01",
                                  "12345678901 01",
                                  "1.0 01\r\r",
                                  "1.5 01\r \r",
                                  "\xEF\xBB\xBF"
                                  "1.5 01"};
  for (const char* refused : kRefused) {
    lines.resize(500 + pick(3000));
    for (auto& line : lines) line = good_line(seconds);
    lines.emplace_back(refused);
    lines.push_back(good_line(seconds));
    const Reading r = expect_same(lines);
    EXPECT_NE(r.error.find(fmt::format(":{}: ", lines.size() - 1)), std::string::npos)
        << refused << ": " << r.error;
  }
}

TEST(TextHexReader, MillionLinesStreamWithFlatMemory) {
  TempDir dir;
  constexpr int kLines = 1'000'000;
  constexpr int kWarmUp = 1000;
  std::string path;
  {
    std::string content = "# baud=9600 parity=E stop=1\n";
    content.reserve(30U * kLines);
    char line[64];
    for (int i = 0; i < kLines; ++i) {
      // 1 ms apart, 1 to 8 bytes a line: 0x00, 0x01, ... so the sum can be checked.
      const int n = 1 + i % 8;
      int len = std::snprintf(line, sizeof line, "%d.%03d", 1000 + i / 1000, i % 1000);
      for (int k = 0; k < n; ++k) {
        len += std::snprintf(line + len, sizeof line - static_cast<std::size_t>(len), " %02x", k);
      }
      content.append(line, static_cast<std::size_t>(len)).push_back('\n');
    }
    path = dir.write("big.hex", content);
  }
  TextHexReader reader(path);
  Chunk chunk;
  std::uint64_t chunks = 0;
  std::uint64_t bytes = 0;
  std::uint64_t byte_sum = 0;
  Nanos last = 0;
  testing::AllocationCounter counter;
  while (reader.next(chunk)) {
    if (chunks == kWarmUp) counter.start();
    ++chunks;
    bytes += chunk.bytes.size();
    for (const auto b : chunk.bytes) byte_sum += b;
    last = chunk.t_end;
  }
  const std::uint64_t allocations = counter.count();
  EXPECT_EQ(chunks, static_cast<std::uint64_t>(kLines));
  EXPECT_EQ(bytes, 4'500'000U);      // (1+2+…+8)/8 = 4.5 bytes a line
  EXPECT_EQ(byte_sum, 10'500'000U);  // (0+1+3+…+28)/8 = 10.5 a line
  EXPECT_EQ(last, 1999 * kNanosPerSecond + 999 * kNanosPerMilli);
  EXPECT_EQ(reader.timestamp_precision(), kNanosPerMilli);
  if (testing::AllocationCounter::available()) {
    EXPECT_EQ(allocations, 0U) << "reading allocated after warm-up";
  }
}

}  // namespace
}  // namespace rtu
