// A read whose time went backwards in the input, and which the reader clamped to the time
// before, shows no silence: the clamped time says only that the read came after the one
// before. The frame it starts gets no gap and no t3.5, on every decoding path.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "capture_test_files.hpp"
#include "core/issue.hpp"
#include "replayed_frames.hpp"
#include "text_capture_lines.hpp"

namespace rtu {
namespace {

using test::export_raw;
using test::replayed_frames;
using testing::TempDir;

// 19200 baud: a character is 11 bits, 572,917 ns.
constexpr Nanos kChar = 572'917;
const std::vector<std::uint8_t> kRequest = {0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A};
const std::vector<std::uint8_t> kResponse = {0x01, 0x03, 0x02, 0x00, 0x2A, 0x39, 0x9B};

// A per-byte text capture of the request, then the response whose first byte is stamped
// `first_response_t` (the rest follow it a character apart).
std::string per_byte_capture(const TempDir& dir, Nanos first_response_t) {
  std::string text = "# baud=19200 parity=E stop=1\n";
  const auto line = [&](Nanos t, std::uint8_t byte) { text += test::text_hex_line(t, {&byte, 1}); };
  Nanos t = 10 * kNanosPerMilli;
  for (const std::uint8_t byte : kRequest) line(t += kChar, byte);
  t = first_response_t;
  line(t, kResponse[0]);
  for (std::size_t i = 1; i < kResponse.size(); ++i) line(t += kChar, kResponse[i]);
  return dir.write("back.hex", text);
}

Nanos request_end() {
  return 10 * kNanosPerMilli + static_cast<Nanos>(kRequest.size()) * kChar;
}

TEST(ClampedTime, ARecordAfterATimeThatWentBackHasNoGapAndNoT35) {
  TempDir dir;
  // The response's first byte is stamped 3 ms before the request ended.
  const auto path = per_byte_capture(dir, request_end() - 3 * kNanosPerMilli);
  for (const bool frame_ahead : {false, true}) {
    const auto frames = replayed_frames(path, frame_ahead);
    ASSERT_EQ(frames.size(), 2U) << "frame_ahead " << frame_ahead;
    EXPECT_TRUE(frames[0].crc_ok);
    EXPECT_TRUE(frames[1].crc_ok);
    EXPECT_EQ(frames[1].gap_before, kUnknownTime) << "frame_ahead " << frame_ahead;
    EXPECT_FALSE(frames[1].issues.has(IssueId::kT35)) << "frame_ahead " << frame_ahead;
  }
}

// A raw export writes the clamped time, in order, and says it was clamped: decoding the
// export gives the same frames as decoding the capture.
TEST(ClampedTime, ARawExportKeepsTheMark) {
  TempDir dir;
  const auto path = per_byte_capture(dir, request_end() - 3 * kNanosPerMilli);
  const std::string exported = (dir.path() / "export.pcapng").string();
  export_raw(path, exported);
  const auto frames = replayed_frames(exported, false);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_EQ(frames[1].gap_before, kUnknownTime);
  EXPECT_FALSE(frames[1].issues.has(IssueId::kT35));
}

// The counterpart: the same response stamped right at the request's end, as the input says
// and not clamped, does show that it left no silence.
TEST(ClampedTime, TheSameRecordStampedInOrderShowsItsMissingSilence) {
  TempDir dir;
  const auto path = per_byte_capture(dir, request_end() + kChar);
  for (const bool frame_ahead : {false, true}) {
    const auto frames = replayed_frames(path, frame_ahead);
    ASSERT_EQ(frames.size(), 2U) << "frame_ahead " << frame_ahead;
    ASSERT_NE(frames[1].gap_before, kUnknownTime) << "frame_ahead " << frame_ahead;
    EXPECT_LT(frames[1].gap_before, kNanosPerMicro) << "frame_ahead " << frame_ahead;
    EXPECT_TRUE(frames[1].issues.has(IssueId::kT35)) << "frame_ahead " << frame_ahead;
  }
}

}  // namespace
}  // namespace rtu
