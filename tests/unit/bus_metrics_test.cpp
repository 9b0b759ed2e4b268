// The Prometheus exposition: the writer's spelling (escapes, values, HELP/TYPE order), and
// the metrics of a crafted bus checked against the text format 0.0.4 by a small reader
// (one HELP and TYPE per family before its samples, no duplicate series, histogram buckets
// cumulative with +Inf equal to _count; promtool misses several of these, FORMATS §11.2),
// and against the report's statistics of the same records.
#include "report/bus_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "dissect/device_stage.hpp"
#include "dissect/device_table.hpp"
#include "pipeline/decode_pipeline.hpp"
#include "pipeline/record_fanout.hpp"
#include "report/prometheus_text.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::with_crc;

constexpr Nanos kMs = kNanosPerMilli;

// ---- a reader of the text format, strict where the format is -----------------------------

struct Sample {
  std::string name;
  std::map<std::string, std::string> labels;  // unescaped values
  double value = 0.0;
};

struct Exposition {
  std::map<std::string, std::string> types;  // family → type
  std::vector<Sample> samples;
  std::vector<std::string> errors;

  [[nodiscard]] double value(const std::string& name,
                             const std::map<std::string, std::string>& labels) const {
    for (const Sample& s : samples) {
      if (s.name == name && s.labels == labels) return s.value;
    }
    return NAN;
  }
  [[nodiscard]] double sum(const std::string& name, const std::string& label = "",
                           const std::string& label_value = "") const {
    double total = 0.0;
    for (const Sample& s : samples) {
      if (s.name != name) continue;
      if (!label.empty() && (!s.labels.contains(label) || s.labels.at(label) != label_value)) {
        continue;
      }
      total += s.value;
    }
    return total;
  }
};

// The family a sample belongs to: its name, or a histogram's name without the suffix.
std::string family_of(const std::string& name, const std::map<std::string, std::string>& types) {
  for (const char* suffix : {"_bucket", "_sum", "_count"}) {
    const std::string s(suffix);
    if (name.size() > s.size() && name.ends_with(s)) {
      const std::string base = name.substr(0, name.size() - s.size());
      if (types.contains(base) && types.at(base) == "histogram") return base;
    }
  }
  return name;
}

// [a-zA-Z_:][a-zA-Z0-9_:]* for metric names, without the colons for label names. (No
// std::regex: GCC 12 warns inside it at -O1.)
bool valid_name(const std::string& name, bool colon) {
  if (name.empty()) return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' ||
                    (colon && c == ':') || (i > 0 && c >= '0' && c <= '9');
    if (!ok) return false;
  }
  return true;
}

// "# HELP name text" / "# TYPE name type": the name and the rest, if `line` is one.
bool comment_line(const std::string& line, const std::string& kind, std::string& name,
                  std::string& rest) {
  const std::string head = "# " + kind + " ";
  if (!line.starts_with(head)) return false;
  const std::size_t space = line.find(' ', head.size());
  name = line.substr(head.size(),
                     space == std::string::npos ? std::string::npos : space - head.size());
  rest = space == std::string::npos ? "" : line.substr(space + 1);
  return valid_name(name, true);
}

// Parses `{a="x",b="y\"z"}`; false on any syntax error (unknown escape included).
bool parse_labels(const std::string& text, std::size_t& i,
                  std::map<std::string, std::string>& out) {
  ++i;  // '{'
  while (i < text.size() && text[i] != '}') {
    const std::size_t eq = text.find('=', i);
    if (eq == std::string::npos) return false;
    const std::string name = text.substr(i, eq - i);
    if (!valid_name(name, false) || name.starts_with("__")) return false;
    i = eq + 1;
    if (i >= text.size() || text[i] != '"') return false;
    ++i;
    std::string value;
    while (i < text.size() && text[i] != '"') {
      if (text[i] == '\\') {
        if (i + 1 >= text.size()) return false;
        const char e = text[i + 1];
        if (e == 'n') {
          value += '\n';
        } else if (e == '\\' || e == '"') {
          value += e;
        } else {
          return false;
        }
        i += 2;
      } else {
        if (text[i] == '\n') return false;
        value += text[i++];
      }
    }
    if (i >= text.size()) return false;
    ++i;                                                 // closing quote
    if (!out.emplace(name, value).second) return false;  // a label twice
    if (i < text.size() && text[i] == ',') ++i;
  }
  if (i >= text.size()) return false;
  ++i;  // '}'
  return true;
}

Exposition read_exposition(const std::string& text) {
  Exposition e;
  if (text.empty() || text.back() != '\n') e.errors.emplace_back("no final newline");
  std::set<std::string> helped;
  std::set<std::string> finished;  // families whose samples are over
  std::set<std::string> series;
  std::string current;
  std::istringstream in(text);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string where = "line " + std::to_string(n) + ": ";
    std::string name;
    std::string rest;
    if (comment_line(line, "HELP", name, rest)) {
      if (!helped.insert(name).second) e.errors.push_back(where + "second HELP");
      continue;
    }
    if (comment_line(line, "TYPE", name, rest)) {
      if (rest != "counter" && rest != "gauge" && rest != "histogram") {
        e.errors.push_back(where + "unknown type " + rest);
      }
      if (e.types.contains(name)) e.errors.push_back(where + "second TYPE");
      if (!helped.contains(name)) e.errors.push_back(where + "TYPE before HELP");
      e.types[name] = rest;
      if (!current.empty()) finished.insert(current);
      current = name;
      continue;
    }
    if (line.starts_with("#")) {
      e.errors.push_back(where + "unknown comment");
      continue;
    }
    Sample s;
    std::size_t i = line.find_first_of("{ ");
    if (i == std::string::npos) {
      e.errors.push_back(where + "no value");
      continue;
    }
    s.name = line.substr(0, i);
    if (!valid_name(s.name, true)) e.errors.push_back(where + "bad name");
    if (line[i] == '{' && !parse_labels(line, i, s.labels)) {
      e.errors.push_back(where + "bad labels");
      continue;
    }
    if (i >= line.size() || line[i] != ' ') {
      e.errors.push_back(where + "no space before the value");
      continue;
    }
    const std::string value = line.substr(i + 1);
    if (value == "+Inf") {
      s.value = INFINITY;
    } else if (value == "-Inf") {
      s.value = -INFINITY;
    } else if (value == "NaN") {
      s.value = NAN;
    } else {
      std::size_t used = 0;
      s.value = std::stod(value, &used);
      if (used != value.size()) e.errors.push_back(where + "bad value " + value);
    }
    const std::string family = family_of(s.name, e.types);
    if (family != current) e.errors.push_back(where + "sample outside its family's block");
    if (!e.types.contains(family)) e.errors.push_back(where + "sample without TYPE");
    if (finished.contains(family)) e.errors.push_back(where + "family split");
    std::string key = s.name;
    for (const auto& [k, v] : s.labels) key += "|" + k + "=" + v;
    if (!series.insert(key).second) e.errors.push_back(where + "duplicate series " + key);
    if (e.types[family] == "counter" && !s.name.ends_with("_total")) {
      e.errors.push_back(where + "counter without _total");
    }
    e.samples.push_back(std::move(s));
  }
  return e;
}

// Every histogram series: buckets non-decreasing in `le`, a +Inf bucket equal to _count.
std::vector<std::string> histogram_errors(const Exposition& e) {
  std::vector<std::string> errors;
  for (const auto& [family, type] : e.types) {
    if (type != "histogram") continue;
    std::map<std::map<std::string, std::string>, std::vector<std::pair<double, double>>> buckets;
    for (const Sample& s : e.samples) {
      if (s.name != family + "_bucket") continue;
      auto labels = s.labels;
      if (!labels.contains("le")) {
        errors.push_back(family + ": bucket without le");
        continue;
      }
      const std::string le = labels.at("le");
      labels.erase("le");
      buckets[labels].emplace_back(le == "+Inf" ? static_cast<double>(INFINITY) : std::stod(le),
                                   s.value);
    }
    for (const auto& [labels, list] : buckets) {
      for (std::size_t i = 1; i < list.size(); ++i) {
        if (!(list[i].first > list[i - 1].first)) errors.push_back(family + ": le not rising");
        if (list[i].second < list[i - 1].second) errors.push_back(family + ": not cumulative");
      }
      if (list.empty() || !std::isinf(list.back().first)) {
        errors.push_back(family + ": no +Inf bucket");
        continue;
      }
      if (list.back().second != e.value(family + "_count", labels)) {
        errors.push_back(family + ": +Inf bucket differs from _count");
      }
      if (std::isnan(e.value(family + "_sum", labels))) errors.push_back(family + ": no _sum");
    }
  }
  return errors;
}

// ---- the writer -------------------------------------------------------------------------

TEST(ExpositionWriter, EscapesLabelValuesAndHelpAsTheFormatSays) {
  EXPECT_EQ(escape_label_value("line \"A\" voltage\\raw\nx"), "line \\\"A\\\" voltage\\\\raw\\nx");
  ExpositionWriter w;
  w.family("x_total", MetricType::kCounter, "a \\ and a\nnewline \"kept\"");
  w.sample("x_total", {{"name", "a\"b\\c\nd"}}, 3);
  EXPECT_EQ(w.text(),
            "# HELP x_total a \\\\ and a\\nnewline \"kept\"\n"
            "# TYPE x_total counter\n"
            "x_total{name=\"a\\\"b\\\\c\\nd\"} 3\n");
  const Exposition e = read_exposition(w.text());
  EXPECT_TRUE(e.errors.empty()) << e.errors.front();
  EXPECT_EQ(e.samples.at(0).labels.at("name"), "a\"b\\c\nd");  // reads back as written
}

TEST(ExpositionWriter, SpellsValuesTheFormatsWay) {
  EXPECT_EQ(format_sample_value(42), "42");
  EXPECT_EQ(format_sample_value(0), "0");
  EXPECT_EQ(format_sample_value(0.0005), "0.0005");
  EXPECT_EQ(format_sample_value(-2.5), "-2.5");
  EXPECT_EQ(format_sample_value(INFINITY), "+Inf");
  EXPECT_EQ(format_sample_value(-INFINITY), "-Inf");
  EXPECT_EQ(format_sample_value(NAN), "NaN");
  EXPECT_EQ(format_sample_value(1e300), "1e+300");
}

TEST(ExpositionWriter, RefusesWhatWouldBreakAScrape) {
  ExpositionWriter w;
  w.family("a_total", MetricType::kCounter, "a");
  EXPECT_THROW(w.family("a_total", MetricType::kCounter, "again"), std::logic_error);
  EXPECT_THROW(w.sample("b_total", {}, 1), std::logic_error);  // not the current family
  EXPECT_THROW(w.sample("a_total", {{"bad-name", "x"}}, 1), std::logic_error);
  EXPECT_THROW(w.sample("a_total", {{"__reserved", "x"}}, 1), std::logic_error);
  EXPECT_THROW(w.family("9lives", MetricType::kGauge, "x"), std::logic_error);
  w.family("h_seconds", MetricType::kHistogram, "h");
  EXPECT_NO_THROW(w.sample("h_seconds_bucket", {{"le", "+Inf"}}, 0));
  EXPECT_THROW(w.sample("h_seconds_total", {}, 0), std::logic_error);
}

TEST(ExpositionReader, CatchesWhatPromtoolDoesNot) {
  // The reader itself must fail where it should, or the tests below prove nothing.
  EXPECT_FALSE(read_exposition("# HELP a_total x\n# TYPE a_total counter\na_total 1\na_total 2\n")
                   .errors.empty());  // duplicate series
  EXPECT_FALSE(
      read_exposition("# HELP a_total x\n# TYPE a_total counter\na_total 1").errors.empty());
  EXPECT_FALSE(read_exposition("# HELP a_total x\n# TYPE a_total counter\na_total{x=\"\\q\"} 1\n")
                   .errors.empty());
  const Exposition h = read_exposition(
      "# HELP h x\n# TYPE h histogram\nh_bucket{le=\"1\"} 2\nh_bucket{le=\"2\"} 1\n"
      "h_sum 3\nh_count 2\n");
  EXPECT_EQ(histogram_errors(h).size(), 2U);  // not cumulative, and no +Inf
}

// ---- the metrics of a bus -----------------------------------------------------------------

// Slave 1 answers three reads (4, 8 and 30 ms), slave 2 answers one with an exception, slave
// 3 never answers, and a response to slave 1 arrives with its CRC broken.
BusBuilder crafted_bus() {
  BusBuilder bus;
  const auto read1 = with_crc({1, 3, 0, 0, 0, 1});
  for (const Nanos latency : {4 * kMs, 8 * kMs, 30 * kMs}) {
    bus.add(read1, 50 * kMs).add(with_crc({1, 3, 2, 0x12, 0x34}), latency);
  }
  bus.add(with_crc({2, 6, 0, 1, 0, 9}), 50 * kMs).add(with_crc({2, 0x86, 2}), 5 * kMs);
  bus.add(with_crc({3, 3, 0, 0, 0, 2}), 50 * kMs);
  bus.add(read1, 1500 * kMs);
  auto broken = with_crc({1, 3, 2, 0x12, 0x34});
  broken.back() ^= 0xFFU;
  bus.add(broken, 6 * kMs);
  bus.add(read1, 50 * kMs).add(with_crc({1, 3, 2, 0x12, 0x35}), 3 * kMs);
  return bus;
}

struct MeteredRun {
  dissect::DeviceTable table;
  TrafficStats stats{&table};
  BusMetrics metrics{"cabinet \"4\"", stats};
  Nanos end = 0;
};

void run(MeteredRun& r, const BusBuilder& bus) {
  RecordFanout sinks;
  sinks.add(r.stats);
  sinks.add(r.metrics);
  dissect::DeviceStage stage(r.table, sinks, true);
  PipelineOptions o;
  o.line = bus.line();
  o.timing_resolution = kNanosPerMicro;
  o.per_byte_timing = true;
  CaptureInfo info;
  info.source = "crafted";
  info.line = bus.line();
  info.timing_resolution = kNanosPerMicro;
  info.per_byte_timing = true;
  DecodePipeline pipeline(o, stage);
  pipeline.start(info);
  for (const Chunk& c : bus.per_byte()) {
    pipeline.push(c);
    r.end = c.t_end;
  }
  pipeline.finish();
}

TEST(BusMetrics, ExpositionFollowsTheFormat) {
  MeteredRun r;
  run(r, crafted_bus());
  ToolHealth health;
  health.recording = true;
  health.capture_files = 3;
  health.seconds_since_last_byte = 0.25;
  const std::string text = r.metrics.exposition(r.end, health);
  const Exposition e = read_exposition(text);
  for (const auto& error : e.errors) ADD_FAILURE() << error;
  for (const auto& error : histogram_errors(e)) ADD_FAILURE() << error;
  // Every sample carries the bus name, escaped in the text and intact when read back.
  EXPECT_NE(text.find(R"(bus="cabinet \"4\"")"), std::string::npos);
  for (const Sample& s : e.samples) EXPECT_EQ(s.labels.at("bus"), "cabinet \"4\"") << s.name;
  EXPECT_EQ(e.value("rtuscope_capture_rotations_total", {{"bus", "cabinet \"4\""}}), 2);
  EXPECT_EQ(e.value("rtuscope_seconds_since_last_byte", {{"bus", "cabinet \"4\""}}), 0.25);
}

TEST(BusMetrics, CountsAgreeWithTheReportsStatistics) {
  MeteredRun r;
  run(r, crafted_bus());
  const Exposition e = read_exposition(r.metrics.exposition(r.end, ToolHealth{}));
  ASSERT_TRUE(e.errors.empty()) << e.errors.front();
  const Totals& t = r.stats.totals();
  EXPECT_EQ(e.sum("rtuscope_frames_total"), static_cast<double>(t.frames));
  EXPECT_EQ(e.sum("rtuscope_bytes_total"), static_cast<double>(t.bytes));
  EXPECT_EQ(e.sum("rtuscope_requests_total"), static_cast<double>(t.requests));
  EXPECT_EQ(e.sum("rtuscope_responses_total"), static_cast<double>(t.responses));
  EXPECT_EQ(e.sum("rtuscope_exceptions_total"), static_cast<double>(t.exceptions));
  EXPECT_EQ(e.sum("rtuscope_timeouts_total"), static_cast<double>(t.timeouts));
  EXPECT_EQ(e.sum("rtuscope_crc_errors_total"), static_cast<double>(t.issues[IssueId::kCrc]));

  // What the crafted bus holds, slave by slave.
  EXPECT_EQ(e.sum("rtuscope_requests_total", "slave", "1"), 5);
  EXPECT_EQ(e.sum("rtuscope_timeouts_total", "slave", "3"), 1);
  EXPECT_EQ(e.sum("rtuscope_exceptions_total", "code", "2"), 1);
  EXPECT_EQ(e.sum("rtuscope_responses_total", "function", "write_single_register"), 1);
  EXPECT_EQ(e.sum("rtuscope_crc_errors_total", "slave", "1"), 1);
  EXPECT_EQ(e.sum("rtuscope_issues_total", "issue", "timeout"),
            static_cast<double>(t.issues[IssueId::kTimeout]));

  // Latencies: the report's count per slave, in the right buckets.
  for (const unsigned slave : {1U, 2U}) {
    const std::map<std::string, std::string> labels = {{"bus", "cabinet \"4\""},
                                                       {"slave", std::to_string(slave)}};
    EXPECT_EQ(
        e.value("rtuscope_response_latency_seconds_count", labels),
        static_cast<double>(r.stats.slave(static_cast<std::uint8_t>(slave))->latency.count()));
  }
  auto bucket = [&](const char* le) {
    return e.value("rtuscope_response_latency_seconds_bucket",
                   {{"bus", "cabinet \"4\""}, {"slave", "1"}, {"le", le}});
  };
  EXPECT_EQ(bucket("0.002"), 0);
  EXPECT_EQ(bucket("0.005"), 2);  // 3 ms and 4 ms (the start of a response, after the request)
  EXPECT_EQ(bucket("0.01"), 3);
  EXPECT_EQ(bucket("0.05"), 4);
  EXPECT_EQ(bucket("+Inf"), 4);  // the broken response has no latency to count
  EXPECT_NEAR(
      e.value("rtuscope_response_latency_seconds_sum", {{"bus", "cabinet \"4\""}, {"slave", "1"}}),
      0.045, 0.001);
}

TEST(BusMetrics, UtilisationCoversTheLastTenSeconds) {
  MeteredRun r;
  run(r, crafted_bus());
  const double now_ratio = r.metrics.utilisation(r.end);
  EXPECT_GT(now_ratio, 0.0);
  EXPECT_LE(now_ratio, 1.0);
  // The same busy time over the whole capture (under 10 s): the report's utilisation.
  EXPECT_NEAR(now_ratio, r.stats.totals().utilisation(), 0.02);
  // Quiet for 20 s: nothing in the window.
  EXPECT_EQ(r.metrics.utilisation(r.end + 20 * kNanosPerSecond), 0.0);
}

}  // namespace
}  // namespace rtu
