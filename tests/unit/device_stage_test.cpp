// The device stage with the bundled maps of dissectors/: named, scaled points with units for
// mapped slaves, raw registers for the others, values only from confirmed, trustworthy
// exchanges, device issues on the record and in the report's counts; the identifier's
// confidence rule; and the time axis labels of the HTML charts.
#include "dissect/device_stage.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/time_format.hpp"
#include "dissect/map_identifier.hpp"
#include "dissect_test_support.hpp"
#include "report/findings.hpp"
#include "report/svg_chart.hpp"
#include "report/traffic_stats.hpp"

namespace rtu::dissect::testing {
namespace {

struct Sample {
  Nanos t = 0;
  unsigned slave = 0;
  std::string point;
  double value = 0.0;
  std::string unit;
};

// What the sinks after the stage see: every value, and the last record's issues.
class Collect : public RecordSink {
 public:
  void on_record(Record& r) override {
    issues = r.issues;
    if (r.device == nullptr) return;
    for (const PointValue& v : r.device->values) {
      samples.push_back({v.t, v.slave, std::string(v.point), v.value, std::string(v.unit)});
    }
  }
  [[nodiscard]] const Sample* find(std::string_view point) const {
    for (const auto& s : samples) {
      if (s.point == point) return &s;
    }
    return nullptr;
  }
  std::vector<Sample> samples;
  IssueSet issues;
};

// Runs request/response pairs (hex without CRC) through a device stage, like the pipeline
// would: the response points at its request and starts later.
class Exchange {
 public:
  explicit Exchange(DeviceTable& table, bool collect_values = true)
      : stage_(table, sink, collect_values) {}
  void run(std::string_view request_hex, std::string_view response_hex) {
    request_ = made_frame(request_hex, Role::kRequest, seq_++);
    request_.t_start = t_;
    stage_.on_record(request_);
    Record response = made_frame(response_hex, Role::kResponse, seq_++);
    response.t_start = t_ + 20 * kNanosPerMilli;
    response.request = &request_;
    stage_.on_record(response);
    t_ += kNanosPerSecond;
  }
  // A request nobody answers: it carries no confirmed value.
  void request_only(std::string_view request_hex) {
    request_ = made_frame(request_hex, Role::kRequest, seq_++);
    stage_.on_record(request_);
  }
  Collect sink;

 private:
  DeviceStage stage_;
  Record request_;
  std::uint64_t seq_ = 0;
  Nanos t_ = 5 * kNanosPerSecond;
};

// The only value collected must be `point` = `value` `unit`.
void expect_only(const Collect& c, std::string_view point, double value, std::string_view unit) {
  ASSERT_EQ(c.samples.size(), 1U);
  EXPECT_EQ(c.samples[0].point, point);
  EXPECT_DOUBLE_EQ(c.samples[0].value, value);
  EXPECT_EQ(c.samples[0].unit, unit);
}

const DeviceMap& map(std::string_view model) {
  const DeviceMap* m = bundled_maps().find(model);
  if (m == nullptr) throw std::invalid_argument("no bundled map");
  return *m;
}

// Slave 1 is a YW2050 named by the user; every other slave is raw registers.
class MixedBus : public ::testing::Test {
 protected:
  MixedBus() { table.assign(1, map("yw2050"), ModelOrigin::kConfigured); }
  DeviceTable table;
  Exchange ex{table};
};

TEST_F(MixedBus, Yw2050FrequencyIsNamedScaledAndInHertz) {
  // F at byte address 0x0036, one register; raw 46816 × 0.00106813 Hz = 50.00558 Hz, given
  // to the map's 3 decimals like `decode` shows it.
  ex.run("01 03 00 36 00 01", "01 03 02 B6 E0");
  expect_only(ex.sink, "F", 50.006, "Hz");
  EXPECT_EQ(ex.sink.samples[0].slave, 1U);
  // At the start of the response.
  EXPECT_EQ(ex.sink.samples[0].t, 5 * kNanosPerSecond + 20 * kNanosPerMilli);
  EXPECT_EQ(table.model(1), "yw2050");
  EXPECT_FALSE(table.identified(1));
}

TEST(DeviceStage, VoltagesScaleByThePtRatioLearnedFromTheTraffic) {
  DeviceTable source;
  source.assign(1, map("yw2050"), ModelOrigin::kConfigured);
  Exchange ex(source);
  ex.run("01 03 00 00 00 01", "01 03 02 59 C4");  // Ua raw 22980 × 0.01 V, PT default 1
  ASSERT_NE(ex.sink.find("Ua"), nullptr);
  EXPECT_NEAR(ex.sink.find("Ua")->value, 229.8, 1e-9);
  EXPECT_EQ(ex.sink.find("Ua")->unit, "V");
  ex.sink.samples.clear();
  ex.run("01 03 03 0E 00 02", "01 03 04 00 0A 00 00");  // PT = 10 (low word first)
  ASSERT_NE(ex.sink.find("PT"), nullptr);
  EXPECT_DOUBLE_EQ(ex.sink.find("PT")->value, 10.0);
  ex.sink.samples.clear();
  ex.run("01 03 00 00 00 01", "01 03 02 59 C4");
  ASSERT_NE(ex.sink.find("Ua"), nullptr);
  EXPECT_NEAR(ex.sink.find("Ua")->value, 2298.0, 1e-9);
}

TEST(DeviceStage, Th900SetValueLeavesTheSpareRegisterOut) {
  DeviceTable source;
  source.assign(3, map("th900"), ModelOrigin::kIdentified);
  Exchange ex(source);
  ex.run("03 03 00 00 00 02", "03 03 04 02 BC 00 00");
  expect_only(ex.sink, "SV", 70.0, "");  // the manual does not say °C or °F
  EXPECT_EQ(source.model(3), "th900");
  EXPECT_TRUE(source.identified(3));
}

TEST_F(MixedBus, SlavesWithoutAMapGoToTheRawSource) {
  ex.run("07 03 00 32 00 01", "07 03 02 12 34");
  expect_only(ex.sink, "holding 0x0032", 0x1234, "");
  EXPECT_EQ(table.model(7), "");

  // Frame writers need no values: a stage that does not collect them gives none.
  Exchange none(table, false);
  none.run("07 03 00 32 00 01", "07 03 02 12 34");
  none.run("01 03 00 36 00 01", "01 03 02 B6 E0");
  EXPECT_TRUE(none.sink.samples.empty());
}

TEST(DeviceStage, WritesCountOnlyOnceConfirmed) {
  DeviceTable source;
  source.assign(3, map("th900"), ModelOrigin::kConfigured);
  Exchange ex(source);
  ex.request_only("03 06 00 00 03 E8");  // SV = 100.0, never answered
  EXPECT_TRUE(ex.sink.samples.empty());
  ex.run("03 06 00 00 03 E8", "03 06 00 00 03 E8");
  expect_only(ex.sink, "SV", 100.0, "");
}

TEST(DeviceStage, ExceptionsBadCrcAndUndefinedAddressesCarryNoValue) {
  DeviceTable source;
  source.assign(3, map("th900"), ModelOrigin::kConfigured);
  Exchange ex(source);
  ex.run("03 03 00 00 00 02", "03 83 02");  // exception
  EXPECT_TRUE(ex.sink.samples.empty());
  ex.run("03 03 00 01 00 01", "03 03 02 00 00");  // only SV's spare register
  EXPECT_TRUE(ex.sink.samples.empty());
  ex.run("03 03 00 15 00 01", "03 03 02 00 05");  // an address the map does not define
  EXPECT_TRUE(ex.sink.samples.empty());

  Record request = made_frame("03 03 00 00 00 02", Role::kRequest, 100);
  Record response = made_frame("03 03 04 02 BC 00 00", Role::kResponse, 101);
  response.storage[4] ^= 0x01;  // a bit flipped on the line: the CRC no longer fits
  response.crc_ok = false;
  response.request = &request;
  Collect sink;
  DeviceStage stage(source, sink, true);
  stage.on_record(request);
  stage.on_record(response);
  EXPECT_TRUE(sink.samples.empty());
}

TEST(DeviceStage, ReportsUseTheDevicesOwnExceptionMeanings) {
  DeviceTable source;
  source.assign(4, map("yakotec"), ModelOrigin::kConfigured);
  TrafficStats stats(&source);
  std::uint64_t seq = 0;
  for (int i = 0; i < 3; ++i) {
    for (const unsigned slave : {4U, 5U}) {
      // Each slave answers a read with exception 01: YAKOTEC means a CRC error by it.
      Record request =
          made_frame(fmt::format("{:02X} 03 00 0A 00 02", slave), Role::kRequest, seq++);
      Record response = made_frame(fmt::format("{:02X} 83 01", slave), Role::kResponse, seq++);
      request.t_start = static_cast<Nanos>(seq) * kNanosPerSecond;
      response.t_start = request.t_start + 20 * kNanosPerMilli;
      response.request = &request;
      stats.on_record(request);
      stats.on_record(response);
    }
  }
  stats.on_finish();
  EXPECT_EQ(stats.device_model(4), "yakotec");
  EXPECT_EQ(stats.exception_name(4, 1), "CRC error");
  EXPECT_TRUE(stats.device_exception(4, 1));
  EXPECT_EQ(stats.device_model(5), "");
  EXPECT_EQ(stats.exception_name(5, 1), "ILLEGAL FUNCTION");
  EXPECT_FALSE(stats.device_exception(5, 1));
  // A live run identifies models after its last record: the report sees them all the same.
  source.assign(5, map("th900"), ModelOrigin::kIdentified);
  EXPECT_EQ(stats.device_model(5), "th900");
  EXPECT_TRUE(stats.device_model_identified(5));
  EXPECT_FALSE(stats.device_model_identified(4));

  std::vector<std::string> causes(256);
  for (const Finding& f : find_problems(stats)) {
    if (f.key == "exceptions_for_request" && f.slave) causes[*f.slave] = f.cause;
  }
  EXPECT_EQ(causes[4], "the yakotec reports its own exception 01 (CRC error): see its manual");
  EXPECT_NE(causes[5].find("register map in the master"), std::string::npos) << causes[5];
}

TEST(DeviceStage, DeviceIssuesReachTheRecordAndEveryReportCount) {
  DeviceTable table;
  table.assign(3, map("th900"), ModelOrigin::kConfigured);
  TrafficStats stats(&table);
  DeviceStage stage(table, stats, true);
  std::uint64_t seq = 0;
  Nanos t = kNanosPerSecond;
  for (int i = 0; i < 2; ++i) {
    // 0x0015 is no TH900 register: undefined_register on the request.
    Record request = made_frame("03 03 00 15 00 01", Role::kRequest, seq++);
    Record response = made_frame("03 03 02 00 05", Role::kResponse, seq++);
    request.t_start = t;
    response.t_start = t + 20 * kNanosPerMilli;
    response.request = &request;
    stage.on_record(request);
    EXPECT_TRUE(request.issues.has(IssueId::kUndefinedRegister));
    EXPECT_EQ(request.device, nullptr);  // only valid while the sinks after the stage run
    stage.on_record(response);
    t += kNanosPerSecond;
  }
  // Slave 9 has no map: the same read is plain Modbus, no device issue.
  Record request = made_frame("09 03 00 15 00 01", Role::kRequest, seq++);
  request.t_start = t;
  stage.on_record(request);
  EXPECT_FALSE(request.issues.has(IssueId::kUndefinedRegister));

  EXPECT_EQ(stats.totals().issues[IssueId::kUndefinedRegister], 2U);
  ASSERT_NE(stats.slave(3), nullptr);
  EXPECT_EQ(stats.slave(3)->issues[IssueId::kUndefinedRegister], 2U);
  ASSERT_NE(stats.slave(9), nullptr);
  EXPECT_EQ(stats.slave(9)->issues[IssueId::kUndefinedRegister], 0U);
  IssueCounts over_time;
  for (std::size_t b = 0; b < stats.timeline().size(); ++b)
    over_time.merge(stats.timeline()[b].issues);
  EXPECT_EQ(over_time[IssueId::kUndefinedRegister], 2U);
}

SlaveRanking ranking(std::uint64_t requests, std::vector<double> scores) {
  SlaveRanking r;
  r.slave = 1;
  r.requests = requests;
  const auto& maps = bundled_maps().maps();
  for (std::size_t i = 0; i < scores.size(); ++i) {
    MapEvidence e;
    e.map = maps[i % maps.size()].get();
    e.score = scores[i];
    r.maps.push_back(e);
  }
  return r;
}

TEST(DeviceStage, IdentifiedModelsNeverReplaceConfiguredOnes) {
  DeviceTable source;
  source.assign(1, map("yw2300"), ModelOrigin::kConfigured);
  SlaveRanking one = ranking(24, {100.0, 10.0});  // slave 1: the traffic says th900
  SlaveRanking two = one;
  two.slave = 2;
  SlaveRanking three = ranking(24, {100.0, 99.9});
  three.slave = 3;
  source.assign_identified({one, two, three});
  ASSERT_EQ(one.maps[0].map->model, "th900");
  EXPECT_EQ(source.model(1), "yw2300");
  EXPECT_FALSE(source.identified(1));
  EXPECT_EQ(source.model(2), "th900");
  EXPECT_TRUE(source.identified(2));
  EXPECT_EQ(source.map_of(3), nullptr);  // not confident
}

TEST(ConfidentMap, NeedsEnoughRequestsAHighScoreAndAClearLead) {
  EXPECT_NE(confident_map(ranking(24, {100.0, 35.1, 0.0})), nullptr);
  EXPECT_EQ(confident_map(ranking(24, {100.0, 35.1})), bundled_maps().maps()[0].get());
  EXPECT_NE(confident_map(ranking(24, {100.0, 99.0})), nullptr);  // one undefined address
  EXPECT_EQ(confident_map(ranking(24, {100.0, 99.8})), nullptr);  // two maps fit as well
  EXPECT_EQ(confident_map(ranking(6, {100.0, 0.0})), nullptr);    // too few requests
  EXPECT_EQ(confident_map(ranking(15, {59.6, 53.7})), nullptr);   // several models on one address
  EXPECT_EQ(confident_map(ranking(24, {})), nullptr);
}

TEST(TimeAxis, SecondsFromTheStartOnRoundSteps) {
  const svg::TimeAxis axis = svg::time_axis(0, 3.707, 4);
  EXPECT_FALSE(axis.wall_clock);
  EXPECT_EQ(axis.labels, (std::vector<std::string>{"0", "1 s", "2 s", "3 s"}));
  EXPECT_EQ(axis.ticks, (std::vector<double>{0, 1, 2, 3}));

  const svg::TimeAxis long_run = svg::time_axis(12 * kNanosPerSecond, 5400, 4);
  EXPECT_EQ(long_run.labels,
            (std::vector<std::string>{"0", "30 min", "1 h", "1 h 30"}));  // 30 min steps

  const svg::TimeAxis short_run = svg::time_axis(0, 0.35, 4);
  EXPECT_EQ(short_run.labels, (std::vector<std::string>{"0", "0.1 s", "0.2 s", "0.3 s"}));
}

TEST(TimeAxis, WallClockTicksSitOnRoundTimesOfDay) {
  // 2026-11-23 08:15:04.5 UTC
  const Nanos start = 1'795'421'704 * kNanosPerSecond + 500 * kNanosPerMilli;
  ASSERT_GE(start, kWallClockFrom);
  const svg::TimeAxis axis = svg::time_axis(start, 600, 5);
  EXPECT_TRUE(axis.wall_clock);
  EXPECT_EQ(axis.labels, (std::vector<std::string>{"08:16", "08:18", "08:20", "08:22", "08:24"}));
  EXPECT_NEAR(axis.ticks.front(), 55.5, 1e-9);  // 08:16:00 is 55.5 s after the start
  const svg::TimeAxis seconds = svg::time_axis(start, 20, 4);
  EXPECT_EQ(seconds.labels.front(), "08:15:05");
  EXPECT_EQ(seconds.labels[1], "08:15:10");
}

TEST(AxisLabel, DigitsFollowTheStepAndLargeValuesShrink) {
  EXPECT_EQ(svg::axis_label(49.98, 0.01, 50.0), "49.98");
  EXPECT_EQ(svg::axis_label(50.0, 0.01, 50.0), "50.00");
  EXPECT_EQ(svg::axis_label(0.4, 0.2, 0.4), "0.4");
  EXPECT_EQ(svg::axis_label(0.0, 0.2, 0.4), "0");
  EXPECT_EQ(svg::axis_label(5e6, 5e6, 1e7), "5M");
  EXPECT_EQ(svg::axis_label(20000, 10000, 20000), "20k");
  EXPECT_EQ(svg::axis_label(250, 50, 250), "250");
}

}  // namespace
}  // namespace rtu::dissect::testing
