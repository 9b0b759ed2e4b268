// LineCheck: the line settings a capture is decoded with, checked against its byte timing;
// and the warning for settings nothing declared.
#include "framing/line_check.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "bus_builder.hpp"
#include "pipeline/line_warnings.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::with_crc;

constexpr Nanos kMs = kNanosPerMilli;
constexpr Nanos kMicro = kNanosPerMicro;  // the step of a text capture's 6 decimals

LineSettings at(std::uint32_t baud, Parity parity = Parity::kEven) {
  LineSettings line;
  line.baud = baud;
  line.parity = parity;
  return line;
}

// A master polling two slaves: 8-byte requests, 5 to 45-byte responses, as on a real bus.
BusBuilder polling(LineSettings line, int transactions, Nanos pause_in_frames = 0) {
  BusBuilder bus(line);
  for (int i = 0; i < transactions; ++i) {
    const auto slave = static_cast<std::uint8_t>(1 + i % 2);
    const auto count = static_cast<std::uint8_t>(1 + (i * 7) % 20);
    bus.add(with_crc({slave, 0x03, 0x00, 0x10, 0x00, count}), 50 * kMs);
    std::vector<std::uint8_t> body = {slave, 0x03, static_cast<std::uint8_t>(2 * count)};
    for (int r = 0; r < 2 * count; ++r) body.push_back(static_cast<std::uint8_t>(r));
    const std::uint16_t crc = crc16(body);
    body.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
    body.push_back(static_cast<std::uint8_t>(crc >> 8U));
    if (pause_in_frames == 0) {
      bus.add(body, 8 * kMs);
    } else {
      // A device that leaves a pause after every byte it sends.
      bus.add({body[0]}, 8 * kMs);
      for (std::size_t b = 1; b < body.size(); ++b) bus.add({body[b]}, pause_in_frames);
    }
  }
  return bus;
}

// Per-byte host reads, each stamped late by 0-150 µs.
std::vector<Chunk> jittered_per_byte(const BusBuilder& bus, unsigned seed) {
  std::vector<Chunk> chunks = bus.per_byte();
  std::mt19937 rng(seed);
  std::uniform_int_distribution<Nanos> late(0, 150 * kMicro);
  for (Chunk& c : chunks) c.t_end += late(rng);
  return chunks;
}

LineCheck fed(const std::vector<Chunk>& chunks) {
  LineCheck check;
  for (const Chunk& c : chunks) check.add(c);
  return check;
}

TEST(LineCheck, NineSixHundredDecodedAtNineSixHundredIsQuiet) {
  const auto bus = polling(at(9600), 30);
  const LineCheck check = fed(bus.per_byte());
  ASSERT_TRUE(check.byte_spacing(kMicro).has_value());
  EXPECT_NEAR(static_cast<double>(*check.byte_spacing(kMicro)),
              static_cast<double>(at(9600).char_time()), 1e3);
  EXPECT_EQ(check.warning(at(9600), kMicro), std::nullopt);
}

TEST(LineCheck, NineteenTwoHundredDecodedAtNineSixHundredNamesNineteenTwoHundred) {
  const auto bus = polling(at(19200), 15);  // 30 frames
  const auto w = fed(bus.per_byte()).warning(at(9600), kMicro);
  ASSERT_TRUE(w.has_value());
  EXPECT_EQ(*w,
            "bytes arrive 0.573 ms apart, shorter than one character at 9600 baud (1.146 ms): the "
            "line is likely 19200 baud; decode with --baud 19200");
}

TEST(LineCheck, NineSixHundredDecodedAtNineteenTwoHundredNamesNineSixHundred) {
  const auto bus = polling(at(9600), 30);
  const auto w = fed(bus.per_byte()).warning(at(19200), kMicro);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("2.0 characters at 19200 baud"), std::string::npos) << *w;
  EXPECT_NE(w->find("the line is likely 9600 baud; decode with --baud 9600"), std::string::npos)
      << *w;
}

TEST(LineCheck, InfersTheRateAndCharacterSizeFromTheSpacing) {
  LineSettings n1 = at(4800, Parity::kNone);
  const auto eleven = fed(polling(at(38400), 60).per_byte()).infer_line(kMicro);
  const auto ten = fed(polling(n1, 60).per_byte()).infer_line(kMicro);
  ASSERT_TRUE(eleven.has_value());
  ASSERT_TRUE(ten.has_value());
  EXPECT_EQ(eleven->baud, 38400U);
  EXPECT_EQ(eleven->bits_per_char, 11U);
  EXPECT_EQ(ten->baud, 4800U);
  EXPECT_EQ(ten->bits_per_char, 10U);
  EXPECT_GT(eleven->agreeing * 2, eleven->spacings);  // most spacings are back-to-back bytes
}

TEST(LineCheck, AGivenCharacterSizeOnlyInfersTheRate) {
  const LineCheck check = fed(polling(at(19200), 60).per_byte());
  EXPECT_EQ(check.infer_line(kMicro, 11U)->baud, 19200U);
  // 19200 at 11 bits is no standard rate at 10 bits (17454): nothing, rather than a guess.
  EXPECT_FALSE(check.infer_line(kMicro, 10U).has_value());
}

TEST(LineCheck, BatchedReadsInferNothing) {
  EXPECT_FALSE(fed(polling(at(19200), 60).batched(16 * kMs)).infer_line(kMicro).has_value());
}

TEST(LineCheck, UsbBatchedChunksCannotBeCheckedAndSayNothing) {
  const auto bus = polling(at(19200), 30);
  const LineCheck check = fed(bus.batched(16 * kMs));
  EXPECT_EQ(check.byte_spacing(kMicro), std::nullopt);
  EXPECT_EQ(check.warning(at(9600), kMicro), std::nullopt);
  EXPECT_EQ(check.warning(at(115200), kMicro), std::nullopt);
}

TEST(LineCheck, LogicAnalyserStartTimesAreUsed) {
  // Saleae exports give each byte's start (t_first_start); the legacy layout has t_end equal.
  const auto bus = polling(at(38400), 20);
  std::vector<Chunk> chunks = bus.per_byte();
  const Nanos char_time = at(38400).char_time();
  for (Chunk& c : chunks) {
    c.t_first_start = c.t_end - char_time;
    c.t_end = c.t_first_start;
  }
  const auto w = fed(chunks).warning(at(9600), kMicro);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("--baud 38400"), std::string::npos) << *w;
  EXPECT_EQ(fed(chunks).warning(at(38400), kMicro), std::nullopt);
}

TEST(LineCheck, ReadJitterDoesNotLookLikeAFasterLine) {
  // Per-byte host reads: each stamp late by 0-150 µs, so some spacings are well under a
  // character, but the spacing most bytes share is still one character.
  const auto bus = polling(at(9600), 40);
  const std::vector<Chunk> chunks = jittered_per_byte(bus, 7);
  const auto spacing = fed(chunks).byte_spacing(kMicro);
  ASSERT_TRUE(spacing.has_value());
  EXPECT_NEAR(static_cast<double>(*spacing), static_cast<double>(at(9600).char_time()), 60e3);
  EXPECT_EQ(fed(chunks).warning(at(9600), kMicro), std::nullopt);
}

TEST(LineCheck, RunsOfOneByteReadsCountAsTheReadsOneByOne) {
  // A per-byte replay hands the check runs of one-byte reads (ByteReads) of any length; it
  // counts a run of spacings in one bucket at a time and carries the bucket across runs.
  // Jittered stamps move the spacings between buckets all the time.
  const auto bus = polling(at(9600), 40);
  const std::vector<Chunk> chunks = jittered_per_byte(bus, 11);
  const test::ByteRun reads(chunks);
  LineCheck in_runs;
  std::size_t run = 1;
  for (std::size_t from = 0; from < chunks.size(); from += run, run = run % 37 + 1) {
    in_runs.add(reads.slice(from, std::min(run, chunks.size() - from), from));
  }
  const auto one_by_one = fed(chunks).infer_line(kMicro);
  const auto by_runs = in_runs.infer_line(kMicro);
  ASSERT_TRUE(one_by_one.has_value());
  ASSERT_TRUE(by_runs.has_value());
  EXPECT_EQ(by_runs->spacing, one_by_one->spacing);
  EXPECT_EQ(by_runs->agreeing, one_by_one->agreeing);
  EXPECT_EQ(by_runs->spacings, one_by_one->spacings);
  EXPECT_EQ(by_runs->spacings, chunks.size() - 1);
  EXPECT_EQ(by_runs->baud, 9600U);
}

TEST(LineCheck, ADeviceThatPausesHalfACharacterIsNotASlowerLine) {
  const LineSettings line = at(19200);
  const auto bus = polling(line, 30, line.char_time() / 2);
  // Measured as 1.5 characters (12800 baud, no standard rate): the pause is the device's.
  const auto spacing = fed(bus.per_byte()).byte_spacing(kMicro);
  ASSERT_TRUE(spacing.has_value());
  EXPECT_NEAR(static_cast<double>(*spacing), 1.5 * static_cast<double>(line.char_time()), 1e3);
  EXPECT_EQ(fed(bus.per_byte()).warning(line, kMicro), std::nullopt);
}

TEST(LineCheck, TooFewBytesOrTooCoarseTimestampsSayNothing) {
  const auto few = polling(at(19200), 1);  // 2 frames
  EXPECT_EQ(fed(few.per_byte()).warning(at(9600), kMicro), std::nullopt);
  const auto many = polling(at(19200), 30);
  EXPECT_EQ(fed(many.per_byte()).warning(at(9600), kMs), std::nullopt);  // 3 decimals
}

TEST(LineCheck, ARateFarFromAnyStandardOneIsGivenAsMeasured) {
  const auto bus = polling(at(25000), 30);
  const auto w = fed(bus.per_byte()).warning(at(9600), kMicro);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("the line is likely 25000 baud; decode with --baud 25000"), std::string::npos)
      << *w;
}

TEST(LineCheck, AnotherCharacterSizeIsNamedWithItsOptions) {
  // 115200 8N1 read as 9600 8E1: at 11 bits a character the spacing would be 126720 baud.
  const auto fast = polling(at(115200, Parity::kNone), 30);
  EXPECT_EQ(fed(fast.per_byte()).warning(at(9600), kMicro),
            "bytes arrive 0.087 ms apart, shorter than one character at 9600 baud (1.146 ms): the "
            "line is likely 115200 baud with 10-bit characters (8N1); decode with --baud 115200 "
            "--parity N --stop 1");
  // 9600 8N1 read as 19200 8E1: 1.8 characters, a standard rate only at 10 bits.
  const auto slow = polling(at(9600, Parity::kNone), 30);
  const auto w = fed(slow.per_byte()).warning(at(19200), kMicro);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("likely 9600 baud with 10-bit characters (8N1)"), std::string::npos) << *w;
}

TEST(LineCheck, StandardBaudRatesAreRecognisedWithinThreePercent) {
  EXPECT_EQ(nearest_standard_baud(19200.0), 19200U);
  EXPECT_EQ(nearest_standard_baud(19500.0), 19200U);
  EXPECT_EQ(nearest_standard_baud(115000.0), 115200U);
  EXPECT_EQ(nearest_standard_baud(57000.0), 57600U);
  EXPECT_EQ(nearest_standard_baud(12800.0), std::nullopt);
  EXPECT_EQ(nearest_standard_baud(126720.0), std::nullopt);  // 115200 at 11 bits for 10
}

TEST(AssumedSettings, NothingGivenNamesTheModbusDefault) {
  EXPECT_EQ(assumed_settings_warning(LineSettings{}, false, LineOverrides{}),
            "no line settings in the capture or on the command line: assumed 9600 8E1 (Modbus "
            "default); use --baud/--parity/--stop");
}

TEST(AssumedSettings, DeclaredOrAllGivenSaysNothing) {
  EXPECT_EQ(assumed_settings_warning(LineSettings{}, true, LineOverrides{}), std::nullopt);
  LineOverrides all;
  all.baud = 19200;
  all.parity = Parity::kNone;
  all.stop_bits = 2;
  EXPECT_EQ(assumed_settings_warning(at(19200, Parity::kNone), false, all), std::nullopt);
}

TEST(AssumedSettings, OnlyTheBaudGivenNamesParityAndStopBits) {
  LineOverrides baud_only;
  baud_only.baud = 19200;
  EXPECT_EQ(assumed_settings_warning(at(19200), false, baud_only),
            "no parity or stop bits in the capture or on the command line: assumed parity E and "
            "1 stop bit (Modbus default), so the line is 19200 8E1; use --parity/--stop");
}

TEST(AddLineWarnings, AssumedSettingsComeBeforeTheTimingCheck) {
  const auto bus = polling(at(19200), 15);
  const LineCheck check = fed(bus.per_byte());
  CaptureInfo info;
  info.source = "capture.csv";
  add_line_warnings(info, false, LineOverrides{}, check, kMicro, false);
  ASSERT_EQ(info.warnings.size(), 2U);
  EXPECT_EQ(info.warnings[0].rfind("no line settings", 0), 0U);
  EXPECT_NE(info.warnings[1].find("--baud 19200"), std::string::npos);
}

}  // namespace
}  // namespace rtu
