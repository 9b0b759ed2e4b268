// The words of the progress line (report/progress_text.hpp): percent, rates and ETA.
#include "report/progress_text.hpp"

#include <gtest/gtest.h>

namespace rtu {
namespace {

TEST(ProgressText, PercentRoundsDownAndStopsAtHundred) {
  EXPECT_EQ(progress_percent(0, 1000), 0);
  EXPECT_EQ(progress_percent(430, 1000), 43);
  // Not "100%" while a byte is left: 100 means done.
  EXPECT_EQ(progress_percent(999, 1000), 99);
  EXPECT_EQ(progress_percent(1000, 1000), 100);
  // A file that grew while it was read.
  EXPECT_EQ(progress_percent(1500, 1000), 100);
  EXPECT_EQ(progress_percent(12'000'000'000ULL, 16'000'000'000ULL), 75);
}

TEST(ProgressText, RatesAndEtaOnceTheyCanBeTold) {
  ProgressFigures f;
  f.label = "decoding 2/2";
  f.bytes = 10'000'000;
  f.size = 40'000'000;
  f.records = 200'000;
  f.seconds = 2.0;
  EXPECT_EQ(progress_text(f), "decoding 2/2   25%  5.0 MB/s  100.0k rec/s  ETA 0:06");

  f.records = 9'000'000;
  f.bytes = 1'000'000;
  f.size = 4'000'000'000;
  f.seconds = 1.0;
  EXPECT_EQ(progress_text(f), "decoding 2/2    0%  1.0 MB/s  9.00M rec/s  ETA 1:06:39");
}

TEST(ProgressText, DashesBeforeThereIsARate) {
  ProgressFigures f;
  f.label = "identifying 1/2";
  f.bytes = 0;
  f.size = 5'000'000;
  f.seconds = 3.0;
  EXPECT_EQ(progress_text(f), "identifying 1/2    0%  -- MB/s  -- rec/s  ETA --:--");
  f.bytes = 1'000'000;
  f.seconds = 0.1;  // too early: the first buffer is no rate
  EXPECT_EQ(progress_text(f), "identifying 1/2   20%  -- MB/s  -- rec/s  ETA --:--");
}

TEST(ProgressText, DoneShowsNoTimeLeft) {
  ProgressFigures f;
  f.label = "exporting 1/2";
  f.bytes = 6'000'000;
  f.size = 6'000'000;
  f.records = 500;
  f.seconds = 3.0;
  EXPECT_EQ(progress_text(f), "exporting 1/2  100%  2.0 MB/s  167 rec/s  ETA 0:00");
}

}  // namespace
}  // namespace rtu
