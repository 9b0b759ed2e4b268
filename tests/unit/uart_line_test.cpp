// The bit-level UART line of the virtual bus: exact cases of a receiver at the wrong
// setting, worked out by hand from the character format.
#include "serial/uart_line.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "core/chunk.hpp"

namespace rtu {
namespace {

std::vector<std::uint8_t> every_byte() {
  std::vector<std::uint8_t> v;
  for (unsigned b = 0; b < 256; ++b) v.push_back(static_cast<std::uint8_t>(b));
  return v;
}

TEST(UartLine, SameSettingsRoundTripEveryByteAtEveryFraming) {
  const auto bytes = every_byte();
  for (const auto& s : {LineSettings{9600, Parity::kEven, 1}, LineSettings{19200, Parity::kNone, 1},
                        LineSettings{115200, Parity::kOdd, 1}, LineSettings{1200, Parity::kNone, 2},
                        LineSettings{250000, Parity::kEven, 1}}) {
    const auto got = transmit_and_receive(bytes, s, s);
    ASSERT_EQ(got.size(), bytes.size()) << s.describe();
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      EXPECT_EQ(got[i].byte, bytes[i]) << s.describe();
      EXPECT_EQ(got[i].error, kLineOk) << s.describe() << " byte " << i;
    }
  }
}

TEST(UartLine, TwiceTheBaudReadsGarbageWithFramingErrors) {
  const std::vector<std::uint8_t> frame = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};
  const auto got = transmit_and_receive(frame, LineSettings{9600, Parity::kEven, 1},
                                        LineSettings{19200, Parity::kEven, 1});
  ASSERT_FALSE(got.empty());
  std::vector<std::uint8_t> values;
  int framing = 0;
  for (const auto& c : got) {
    values.push_back(c.byte);
    if ((c.error & (kFramingError | kBreak)) != 0) ++framing;
  }
  EXPECT_NE(values, frame);
  EXPECT_GT(framing, 0);
  // A start bit at 9600 lasts two bits at 19200: the first character starts on the same
  // edge and still reads the start bit as its d0.
  EXPECT_EQ(got[0].byte & 1U, 0U);
}

TEST(UartLine, TwoStopBitsReadWithEvenParityGiveParityErrorsOnEvenCounts) {
  // 8N2 sent, 8E1 read: the receiver takes the first stop bit (1) for parity and the
  // second (1) for its stop bit. Even parity wants 1 only when the count of ones is odd.
  const std::vector<std::uint8_t> bytes = {0x01, 0x03, 0x07, 0x00, 0xFE, 0xFF};
  const auto got = transmit_and_receive(bytes, LineSettings{9600, Parity::kNone, 2},
                                        LineSettings{9600, Parity::kEven, 1});
  ASSERT_EQ(got.size(), bytes.size());
  const std::vector<std::uint8_t> expected = {kLineOk,      kParityError, kLineOk,
                                              kParityError, kLineOk,      kParityError};
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    EXPECT_EQ(got[i].byte, bytes[i]);
    EXPECT_EQ(got[i].error, expected[i]) << "byte " << i;
  }
}

TEST(UartLine, EvenParityReadAsOddIsAParityErrorOnEveryByte) {
  const auto bytes = every_byte();
  const auto got = transmit_and_receive(bytes, LineSettings{19200, Parity::kEven, 1},
                                        LineSettings{19200, Parity::kOdd, 1});
  ASSERT_EQ(got.size(), bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    EXPECT_EQ(got[i].byte, bytes[i]);
    EXPECT_EQ(got[i].error, kParityError) << "byte " << i;
  }
}

TEST(UartLine, OneStopBitReadWithTwoIsReadAlike) {
  // Receivers check only the first stop bit.
  const auto bytes = every_byte();
  const auto got = transmit_and_receive(bytes, LineSettings{9600, Parity::kNone, 1},
                                        LineSettings{9600, Parity::kNone, 2});
  ASSERT_EQ(got.size(), bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) EXPECT_EQ(got[i].error, kLineOk);
}

TEST(UartLine, InvertedLineGivesBreaksAndFramingErrorsWithInvertedValues) {
  // 0x01 at 8E1 is 0 1 0000000 1 1; inverted, on a line idling at 0: 1 0 1111111 0 0.
  // The fall at bit 1 starts a character: data = bits 2..9 = 1111111 0 → 0x7F, the
  // parity sample (bit 10) is 0 where even parity of 0x7F wants 1, and the stop sample
  // (bit 11) is the low idle line: a framing error.
  const auto s = LineSettings{9600, Parity::kEven, 1};
  auto got = transmit_and_receive({0x01}, s, s, true);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].byte, 0x7F);
  EXPECT_EQ(got[0].error, kFramingError);
  // 0x00 inverted is high from the start bit to the parity bit (even parity 0 → 1) and
  // falls at the stop bit into the low idle line: all zeros, a break.
  got = transmit_and_receive({0x00}, s, s, true);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].byte, 0x00);
  EXPECT_EQ(got[0].error, kBreak);
  // A real frame on a swapped pair: no character arrives clean.
  const auto frame =
      transmit_and_receive({0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD}, s, s, true);
  ASSERT_FALSE(frame.empty());
  for (const auto& c : frame) EXPECT_NE(c.error, kLineOk);
}

TEST(UartLine, ShortLowPulseIsAFalseStartAndALongerOneALoneByte) {
  const auto s = LineSettings{9600, Parity::kEven, 1};
  LineLevels levels;
  levels.set(1000, false);
  levels.set(1000 + half_bits_at(9600, 1) / 2, true);  // a quarter bit low
  UartReceiver receiver(s);
  std::vector<ReceivedChar> out;
  receiver.receive(levels, 10 * char_duration(s), out);
  EXPECT_TRUE(out.empty());
  const Picos t = 3 * char_duration(s);
  levels.set(t, false);
  levels.set(t + half_bits_at(9600, 2), true);  // one bit low: a start bit, then all ones
  receiver.receive(levels, 10 * char_duration(s), out);
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(out[0].byte, 0xFF);
  EXPECT_EQ(out[0].error, kParityError);  // the idle 1 is read as parity; 0xFF wants 0
}

TEST(UartLine, WaitsForTheLineUntilACharacterIsWhole) {
  const auto s = LineSettings{9600, Parity::kNone, 1};
  LineLevels levels;
  const Picos end = render_char(levels, 0, 0x55, s);
  UartReceiver receiver(s);
  std::vector<ReceivedChar> out;
  receiver.receive(levels, end / 2, out);
  EXPECT_TRUE(out.empty());
  ASSERT_TRUE(receiver.next_complete(levels).has_value());
  receiver.receive(levels, *receiver.next_complete(levels), out);
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(out[0].byte, 0x55);
  EXPECT_FALSE(receiver.next_complete(levels).has_value());
}

}  // namespace
}  // namespace rtu
