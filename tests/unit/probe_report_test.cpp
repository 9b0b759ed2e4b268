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

// Eight bursts decide a setting: clean frames in them, or no frame at all. Anything in
// between (frames with flagged bytes: the wrong parity) is listened to for the whole dwell.
TEST(ProbeReport, ASettingIsSettledByEightBurstsThatLeaveNoDoubt) {
  const auto s = LineSettings{9600, Parity::kEven, 1};
  const std::vector<std::uint8_t> request = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};
  const std::vector<std::uint8_t> garbage = {0x13, 0x77, 0x42};
  const std::vector<std::uint8_t> flags(request.size(), kParityError);
  const auto bursts_settle = [&](const std::vector<std::uint8_t>& bytes, bool flagged) {
    EvidenceCounter counter(s, kNanosPerMilli);
    std::vector<bool> settled;
    for (int i = 1; i <= 10; ++i) {
      Chunk chunk;
      chunk.t_end = i * 100 * kNanosPerMilli;
      chunk.bytes = bytes;
      if (flagged) chunk.errors = flags;
      counter.push(chunk);
      settled.push_back(counter.settled());
    }
    return settled;
  };
  // A burst ends when the next one starts: the ninth read closes the eighth burst.
  const auto clean = bursts_settle(request, false);
  EXPECT_FALSE(clean[7]);
  EXPECT_TRUE(clean[8]);
  const auto noise = bursts_settle(garbage, false);
  EXPECT_FALSE(noise[7]);
  EXPECT_TRUE(noise[8]);
  const auto wrong_parity = bursts_settle(request, true);
  EXPECT_FALSE(wrong_parity.back());
}

// Listening that stops inside a burst has not seen how it ends: on a swapped pair that
// burst would count as one not ending in an error.
TEST(ProbeReport, ABurstCutByTheEndOfListeningIsLeftOut) {
  const auto s = LineSettings{9600, Parity::kEven, 1};
  const std::vector<std::uint8_t> bytes = {0x13, 0x77};
  const auto bursts_when_stopped = [&](Nanos stopped_at) {
    EvidenceCounter counter(s, kNanosPerMilli);
    for (int i = 1; i <= 3; ++i) {
      Chunk chunk;
      chunk.t_end = i * 100 * kNanosPerMilli;
      chunk.bytes = bytes;
      counter.push(chunk);
    }
    return counter.finish(300 * kNanosPerMilli, stopped_at).bursts;
  };
  EXPECT_EQ(bursts_when_stopped(300 * kNanosPerMilli + 1), 2U);
  EXPECT_EQ(bursts_when_stopped(400 * kNanosPerMilli), 3U);
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

// At 1200 baud a 0.8 s dwell hears a handful of frames: 8 at one framing and 6 at the
// other is chance, not evidence, and the Modbus rule decides.
TEST(ProbeReport, FewFramesAtASlowRateStillReadAlike) {
  const std::vector<SettingEvidence> table = {clean(LineSettings{1200, Parity::kNone, 1}, 8),
                                              clean(LineSettings{1200, Parity::kEven, 1}, 6)};
  const auto v = judge_probe(table, false);
  ASSERT_TRUE(v.winner.has_value());
  EXPECT_EQ(*v.winner, 1U);
  ASSERT_EQ(v.alike.size(), 1U);
  // A setting that hears a third of the frames is not alike: something there is wrong.
  const auto apart = judge_probe({clean(LineSettings{1200, Parity::kNone, 1}, 9),
                                  clean(LineSettings{1200, Parity::kEven, 1}, 3)},
                                 false);
  ASSERT_TRUE(apart.winner.has_value());
  EXPECT_EQ(*apart.winner, 0U);
  EXPECT_TRUE(apart.alike.empty());
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
  // The bus is 8E1 and probe heard it so: what it says is about a device set to 8O1.
  EXPECT_TRUE(has_diagnosis(v, "a device set to 9600 8O1 on this 9600 8E1 bus would reject"));
  EXPECT_FALSE(has_diagnosis(v, "the parity is wrong"));
  // Without a clean hearing of the bus (probe ran out of time first), try the others.
  const auto alone = judge_probe({odd}, false);
  EXPECT_TRUE(has_diagnosis(alone, "the parity is wrong, try even or none"));
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

TEST(ProbeReport, OneSettingInTenReadingASwappedPairCleanStillCallsItSwapped) {
  // A full probe hears dozens of settings; now and then one of them hears no error marks
  // (its port lost PARMRK for a while), so its bursts end clean. That one must not hide
  // the pattern.
  std::vector<SettingEvidence> table;
  for (const std::uint32_t baud :
       {1200U, 2400U, 4800U, 9600U, 14400U, 19200U, 38400U, 57600U, 76800U, 115200U}) {
    table.push_back(garbage(LineSettings{baud, Parity::kEven, 1}, 20, 20));
  }
  table.push_back(garbage(LineSettings{4800, Parity::kNone, 2}, 20, 0));
  EXPECT_TRUE(judge_probe(table, false).inverted);
  // Two such settings among eleven are too many: that is no longer one chance alignment.
  table.push_back(garbage(LineSettings{9600, Parity::kNone, 2}, 20, 0));
  EXPECT_FALSE(judge_probe(table, false).inverted);
}

TEST(ProbeReport, BurstsSplitByLateReadsDoNotHideASwappedPair) {
  // A probe of a swapped pair on a loaded machine (ASan, tests side by side): reads that
  // came late split bursts, and the piece before each split ended clean. Three settings
  // ended two or three of their eight bursts so; every other one ended all or all but one
  // in an error.
  std::vector<SettingEvidence> table;
  for (std::uint32_t i = 0; i < 17; ++i) {
    table.push_back(garbage(LineSettings{1200U * (i + 1), Parity::kEven, 1}, 8, 8));
  }
  table.push_back(garbage(LineSettings{9600, Parity::kNone, 2}, 8, 5));
  table.push_back(garbage(LineSettings{9600, Parity::kOdd, 1}, 8, 6));
  table.push_back(garbage(LineSettings{19200, Parity::kNone, 1}, 8, 6));
  table.push_back(garbage(LineSettings{19200, Parity::kEven, 1}, 8, 7));
  table.push_back(garbage(LineSettings{14400, Parity::kNone, 2}, 8, 7));
  EXPECT_TRUE(judge_probe(table, false).inverted);
  // Settings that end most of their bursts clean are straight-line readings: three of
  // twenty-five are more than one in ten.
  table.push_back(garbage(LineSettings{38400, Parity::kNone, 1}, 8, 3));
  table.push_back(garbage(LineSettings{38400, Parity::kNone, 2}, 8, 0));
  table.push_back(garbage(LineSettings{57600, Parity::kNone, 2}, 8, 1));
  EXPECT_FALSE(judge_probe(table, false).inverted);
}

TEST(ProbeReport, AStraightLineAtAnUnlistedRateIsNotCalledSwapped) {
  // What a straight line at 31250 8E1 (no candidate rate) gave on the virtual bus: about
  // half the burst ends in an error overall, and many settings end most bursts clean.
  const std::vector<std::pair<std::uint64_t, std::uint64_t>> ends = {
      {0, 8}, {0, 8}, {7, 8}, {7, 8}, {0, 8}, {8, 8}, {4, 8}, {5, 8}, {5, 8}, {4, 8},
      {5, 8}, {5, 8}, {1, 8}, {2, 8}, {4, 8}, {1, 8}, {6, 8}, {4, 8}, {7, 8}, {8, 9}};
  std::vector<SettingEvidence> table;
  std::uint32_t baud = 1200;
  for (const auto& [flagged, bursts] : ends) {
    table.push_back(garbage(LineSettings{baud, Parity::kEven, 1}, bursts, flagged));
    baud += 1200;
  }
  EXPECT_FALSE(judge_probe(table, false).inverted);
  // Even with every setting that ends most bursts clean left out, the share of ends in an
  // error stays far from a swapped pair's.
  std::vector<SettingEvidence> mostly_flagged;
  for (const auto& e : table) {
    if (2 * e.bursts_ending_flagged >= e.bursts) mostly_flagged.push_back(e);
  }
  EXPECT_FALSE(judge_probe(mostly_flagged, false).inverted);
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
