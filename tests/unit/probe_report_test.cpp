// Judging probe's evidence: counting CRC-valid frames through the real Framer, the Modbus
// rule among settings read alike, and the diagnoses each need their evidence.
#include "report/probe_report.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/chunk.hpp"
#include "framing/setting_evidence.hpp"

namespace rtu {
namespace {

// A clean hearing: `frames` CRC-valid frames of 10 bytes in 1 s, nothing else.
SettingEvidence clean(const LineSettings& s, std::uint64_t frames) {
  SettingEvidence e;
  e.line = s;
  e.listened = kNanosPerSecond;
  e.bytes = frames * 10;
  e.frames = frames;
  e.frame_bytes = frames * 10;
  e.bursts = frames;
  return e;
}

// Garbage: bytes and errors, no frame; `flagged_ends` of `bursts` end in an error.
SettingEvidence garbage(const LineSettings& s, std::uint64_t bursts, std::uint64_t flagged_ends) {
  SettingEvidence e;
  e.line = s;
  e.listened = kNanosPerSecond;
  e.bytes = 100;
  e.framing_errors = 60;
  e.breaks = 5;
  e.bursts = bursts;
  e.bursts_ending_flagged = flagged_ends;
  return e;
}

bool has_diagnosis(const ProbeVerdict& v, const std::string& text) {
  for (const auto& d : v.diagnoses) {
    if (d.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(ProbeReport, CountsCrcValidFramesThroughTheFramer) {
  const auto s = LineSettings{9600, Parity::kEven, 1};
  EvidenceCounter counter(s, kNanosPerMilli);
  // FC03 request for 10 registers at slave 1, then a lone glitch byte long after.
  const std::vector<std::uint8_t> request = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};
  Chunk chunk;
  chunk.t_end = kNanosPerSecond;
  chunk.bytes = request;
  counter.push(chunk);
  const std::vector<std::uint8_t> glitch = {0xFF};
  const std::vector<std::uint8_t> flag = {kParityError};
  chunk.t_end = 2 * kNanosPerSecond;
  chunk.bytes = glitch;
  chunk.errors = flag;
  counter.push(chunk);
  const auto e = counter.finish(2 * kNanosPerSecond);
  EXPECT_EQ(e.frames, 1U);
  EXPECT_EQ(e.frame_bytes, 8U);
  EXPECT_EQ(e.bytes, 9U);
  EXPECT_EQ(e.parity_errors, 1U);
  EXPECT_EQ(e.lone_bytes, 1U);
  EXPECT_EQ(e.lone_idle_bytes, 1U);
  EXPECT_EQ(e.bursts, 2U);
  EXPECT_EQ(e.bursts_ending_flagged, 1U);
  EXPECT_DOUBLE_EQ(e.clean_share(), 8.0 / 9.0);
}

TEST(ProbeReport, SettingsReadAlikeAreChosenByTheModbusRule) {
  // 8N1 heard one frame more than 8E1 by chance; the rule still picks even parity.
  const std::vector<SettingEvidence> table = {
      clean(LineSettings{9600, Parity::kNone, 1}, 32),
      clean(LineSettings{9600, Parity::kEven, 1}, 31),
      garbage(LineSettings{19200, Parity::kEven, 1}, 30, 10)};
  const auto v = judge_probe(table, false);
  ASSERT_TRUE(v.winner.has_value());
  EXPECT_EQ(*v.winner, 1U);
  ASSERT_EQ(v.alike.size(), 1U);
  EXPECT_EQ(v.alike[0], 0U);
  EXPECT_EQ(v.ranking.front(), 1U);
  EXPECT_FALSE(v.inverted);
}

TEST(ProbeReport, EveryByteFlaggedInCrcValidFramesIsTheWrongParity) {
  auto odd = clean(LineSettings{9600, Parity::kOdd, 1}, 30);
  odd.parity_errors = odd.bytes;
  odd.flagged_frame_bytes = odd.frame_bytes;
  const std::vector<SettingEvidence> table = {odd, clean(LineSettings{9600, Parity::kEven, 1}, 30)};
  const auto v = judge_probe(table, false);
  ASSERT_TRUE(v.winner.has_value());
  EXPECT_EQ(table[*v.winner].line.parity, Parity::kEven);
  EXPECT_TRUE(v.alike.empty());
  EXPECT_TRUE(has_diagnosis(v, "parity errors on every byte at 9600 8O1"));
}

TEST(ProbeReport, BurstsEndingInErrorsAtEverySettingAreASwappedPair) {
  const std::vector<SettingEvidence> table = {
      garbage(LineSettings{9600, Parity::kEven, 1}, 20, 20),
      garbage(LineSettings{19200, Parity::kEven, 1}, 20, 19),
      garbage(LineSettings{4800, Parity::kNone, 1}, 10, 10)};
  const auto v = judge_probe(table, false);
  EXPECT_FALSE(v.winner.has_value());
  EXPECT_TRUE(v.inverted);
  EXPECT_TRUE(has_diagnosis(v, "swap A and B"));
  EXPECT_NE(probe_json(table, v).find("\"inverted\":true"), std::string::npos);
}

TEST(ProbeReport, AStraightLineAtWrongSettingsIsNotCalledSwapped) {
  // Some settings end every burst in an error, one does not: not the swapped pattern.
  const std::vector<SettingEvidence> table = {
      garbage(LineSettings{9600, Parity::kEven, 1}, 20, 20),
      garbage(LineSettings{19200, Parity::kEven, 1}, 20, 8)};
  const auto v = judge_probe(table, false);
  EXPECT_FALSE(v.winner.has_value());
  EXPECT_FALSE(v.inverted);
}

TEST(ProbeReport, LoneBytesAtTurnaroundsAreABiasFinding) {
  auto e = clean(LineSettings{9600, Parity::kEven, 1}, 30);
  e.bytes += 30;
  e.parity_errors = 30;
  e.lone_bytes = 30;
  e.lone_idle_bytes = 30;
  const auto v = judge_probe({e}, false);
  ASSERT_TRUE(v.winner.has_value());
  EXPECT_TRUE(has_diagnosis(v, "bias: 30 lone bytes"));
  EXPECT_FALSE(has_diagnosis(v, "rate may be off"));
}

TEST(ProbeReport, FramesOnlyAmidGarbageAtOneRatePointToANeighbouringRate) {
  // A few CRC-valid frames at 9600, most bytes unexplained: no winner, and said why.
  auto near = garbage(LineSettings{9600, Parity::kEven, 1}, 20, 5);
  near.frames = 2;
  near.frame_bytes = 20;
  const std::vector<SettingEvidence> table = {
      near, garbage(LineSettings{19200, Parity::kEven, 1}, 20, 5)};
  const auto v = judge_probe(table, false);
  EXPECT_FALSE(v.winner.has_value());
  EXPECT_TRUE(has_diagnosis(v, "CRC-valid frames only at 9600 8E1"));
}

TEST(ProbeReport, LineErrorsAtTheWinnerThatGlitchesDoNotExplainAreSaid) {
  auto e = clean(LineSettings{19200, Parity::kEven, 1}, 30);
  e.bytes += 40;
  e.framing_errors = 40;  // errors between frames, not lone bytes
  const auto v = judge_probe({e}, false);
  ASSERT_TRUE(v.winner.has_value());
  EXPECT_TRUE(has_diagnosis(v, "line errors even at 19200 8E1"));
  EXPECT_FALSE(has_diagnosis(v, "bias"));
}

TEST(ProbeReport, AQuietBusHasNoWinnerAndSaysSo) {
  SettingEvidence silent;
  silent.line = LineSettings{9600, Parity::kEven, 1};
  silent.listened = kNanosPerSecond;
  const auto v = judge_probe({silent}, true);
  EXPECT_FALSE(v.winner.has_value());
  EXPECT_NE(probe_text({silent}, v, 12).find("quiet"), std::string::npos);
  EXPECT_NE(probe_json({silent}, v).find("\"winner\":null"), std::string::npos);
}

}  // namespace
}  // namespace rtu
