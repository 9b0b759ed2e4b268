// What identification looked at reaches every rendering of the report: JSON names how its
// sample ended, and text and HTML say it, with what to do when the memory bound cut it short.
#include "report/identification_sample.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "capture_test_files.hpp"
#include "report/report_writers.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {
namespace {

std::string rendered(const TrafficStats& stats, const std::string& format) {
  const testing::TempDir dir;
  const std::string path = (dir.path() / ("report." + format)).string();
  {
    OutputStream out(path);
    if (format == "json") write_report_json(out, stats, {});
    if (format == "txt") write_report_text(out, stats, {});
    if (format == "html") write_report_html(out, stats, {});
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(IdentificationSample, EveryRenderingSaysTheBoundCutTheSampleShort) {
  TrafficStats stats;
  stats.note_identification(
      IdentificationSample{200000, 132052, 17, SampleEnd::kHeldBound, 24 * 1024 * 1024});
  EXPECT_NE(rendered(stats, "json")
                .find(R"("identification":{"frames_wanted":200000,"frames":132052,)"
                      R"("noise_bytes":17,"ended":"held_bound"})"),
            std::string::npos);
  const std::string said =
      "models identified from only the first 132052 frames and 17 bytes of noise of 200000 "
      "asked for: the records held for the decoding meanwhile reached their bound of 24 MB";
  EXPECT_NE(rendered(stats, "txt").find(said), std::string::npos);
  std::string note = said;  // a sentence of its own in HTML
  note[0] = 'M';
  EXPECT_NE(rendered(stats, "html").find(note), std::string::npos);
}

TEST(IdentificationSample, NullWhereIdentificationDidNotRun) {
  const TrafficStats stats;
  EXPECT_NE(rendered(stats, "json").find(R"("identification":null)"), std::string::npos);
  EXPECT_EQ(rendered(stats, "txt").find("models identified"), std::string::npos);
}

TEST(IdentificationSample, NamesEachEnd) {
  EXPECT_EQ(sample_end_name(SampleEnd::kEnough), "enough");
  EXPECT_EQ(sample_end_name(SampleEnd::kCaptureEnd), "capture_end");
  EXPECT_EQ(sample_end_name(SampleEnd::kHeldBound), "held_bound");
  EXPECT_EQ(describe(IdentificationSample{8, 8, 0, SampleEnd::kEnough, 0}),
            "models identified from the first 8 frames (--identify-frames 8); slaves first "
            "heard later keep raw registers");
  EXPECT_EQ(describe(IdentificationSample{0, 48, 0, SampleEnd::kCaptureEnd, 0}),
            "models identified from all 48 frames of the capture");
}

}  // namespace
}  // namespace rtu
