// Statistics behind `rtuscope report`: the quantile sketch against a brute-force reference,
// time buckets and utilisation arithmetic, poll periods, and each finding triggered by a
// crafted bus and silent on a clean one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <tuple>
#include <vector>

#include "bus_builder.hpp"
#include "dissect/device_stage.hpp"
#include "pipeline/decode_pipeline.hpp"
#include "report/findings.hpp"
#include "report/log_histogram.hpp"
#include "report/time_buckets.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::with_crc;

constexpr Nanos kMs = kNanosPerMilli;

// ---- LogHistogram ---------------------------------------------------------------------

Nanos brute_quantile(std::vector<Nanos> v, double p) {
  std::sort(v.begin(), v.end());
  if (p <= 0.0) return v.front();
  auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
  rank = std::clamp<std::size_t>(rank, 1, v.size());
  return v[rank - 1];
}

void expect_close(Nanos estimate, Nanos truth) {
  const double tolerance = std::max(static_cast<double>(truth) * LogHistogram::kRelativeError,
                                    static_cast<double>(LogHistogram::kFloor));
  EXPECT_LE(std::abs(static_cast<double>(estimate - truth)), tolerance)
      << "estimate " << estimate << " truth " << truth;
}

TEST(LogHistogram, QuantilesMatchBruteForceOnRandomData) {
  std::mt19937_64 rng(12345);
  std::lognormal_distribution<double> lognormal(std::log(20e6), 0.8);  // ~20 ms latencies
  std::uniform_int_distribution<Nanos> uniform(0, 2 * kNanosPerSecond);
  std::exponential_distribution<double> expo(1.0 / 5e5);
  for (int dist = 0; dist < 3; ++dist) {
    for (const std::size_t n : {1UL, 2UL, 7UL, 100UL, 5000UL}) {
      std::vector<Nanos> values;
      LogHistogram h;
      for (std::size_t i = 0; i < n; ++i) {
        Nanos v = 0;
        if (dist == 0) v = static_cast<Nanos>(lognormal(rng));
        if (dist == 1) v = uniform(rng);
        if (dist == 2) v = static_cast<Nanos>(expo(rng));
        values.push_back(v);
        h.add(v);
      }
      ASSERT_EQ(h.count(), n);
      EXPECT_EQ(h.min(), *std::min_element(values.begin(), values.end()));
      EXPECT_EQ(h.max(), *std::max_element(values.begin(), values.end()));
      for (const double p : {0.0, 0.01, 0.25, 0.5, 0.9, 0.95, 0.99, 0.999, 1.0}) {
        SCOPED_TRACE(::testing::Message() << "dist " << dist << " n " << n << " p " << p);
        expect_close(h.quantile(p), brute_quantile(values, p));
      }
    }
  }
}

// A value lands in the bucket whose bounds hold it, at every edge: each bucket's lower bound
// and the nanosecond below it, over the whole range, and random values.
TEST(LogHistogram, EveryValueLandsInTheBucketThatHoldsIt) {
  const Nanos below_floor = LogHistogram::kFloor - 1;
  const Nanos top = 400 * 24 * 3600 * kNanosPerSecond;  // in the last bucket (from ~1 day)
  const Nanos range = 12 * 3600 * kNanosPerSecond;      // below it
  auto bounds_of = [&](Nanos v) {
    LogHistogram h;
    for (const Nanos x : {below_floor, v, top}) h.add(x);
    std::vector<std::pair<Nanos, Nanos>> buckets;
    h.for_each_bucket([&](Nanos lo, Nanos hi, std::uint64_t) { buckets.emplace_back(lo, hi); });
    return buckets;
  };
  std::vector<Nanos> values;
  Nanos edge = LogHistogram::kFloor;
  while (edge < range) {
    values.push_back(edge);
    values.push_back(edge - 1);
    const auto buckets = bounds_of(edge);
    const auto it = std::find_if(buckets.begin(), buckets.end(), [&](const auto& b) {
      return b.first <= edge && edge <= b.second;
    });
    ASSERT_NE(it, buckets.end()) << edge;
    edge = it->second + 1;  // the next bucket's lower bound
  }
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<Nanos> any(LogHistogram::kFloor, range);
  for (int i = 0; i < 2000; ++i) values.push_back(any(rng));
  for (const Nanos v : values) {
    if (v < LogHistogram::kFloor) continue;
    const auto buckets = bounds_of(v);
    ASSERT_EQ(buckets.size(), 3U) << v;  // below the floor, v's own, the top
    EXPECT_LE(buckets[1].first, v);
    EXPECT_GE(buckets[1].second, v);
  }
}

TEST(LogHistogram, MergeEqualsAddingEverything) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<Nanos> d(-5 * kNanosPerMicro, 900 * kMs);
  LogHistogram a;
  LogHistogram b;
  LogHistogram all;
  for (int i = 0; i < 3000; ++i) {
    const Nanos v = d(rng);
    (i % 3 == 0 ? a : b).add(v);
    all.add(v);
  }
  a.merge(b);
  EXPECT_EQ(a.count(), all.count());
  EXPECT_EQ(a.min(), all.min());
  EXPECT_EQ(a.max(), all.max());
  for (const double p : {0.1, 0.5, 0.99}) EXPECT_EQ(a.quantile(p), all.quantile(p));
}

TEST(LogHistogram, BucketsCoverEverySampleOnce) {
  LogHistogram h;
  for (Nanos v :
       {Nanos{0}, Nanos{500}, 3 * kMs, 3 * kMs + 1, 250 * kMs, 86'000 * kNanosPerSecond}) {
    h.add(v);
  }
  std::uint64_t total = 0;
  Nanos previous_hi = std::numeric_limits<Nanos>::min();
  h.for_each_bucket([&](Nanos lo, Nanos hi, std::uint64_t n) {
    EXPECT_LE(lo, hi);
    EXPECT_GT(lo, previous_hi);
    previous_hi = hi;
    total += n;
  });
  EXPECT_EQ(total, 6U);
}

// ---- TimeBuckets ----------------------------------------------------------------------

struct Sum {
  double v = 0;
  std::uint64_t n = 0;
  void merge(const Sum& o) {
    v += o.v;
    n += o.n;
  }
};

TEST(TimeBuckets, WidenKeepsTotalsAndCoversLateTimes) {
  TimeBuckets<Sum> tb(1000, 10, 8);
  for (Nanos t = 1000; t < 1000 + 1000; t += 7) ++tb.at(t).n;  // 143 samples over 1000 ns
  EXPECT_GE(tb.end(), 2000);
  EXPECT_EQ(tb.width(), 160);  // 10 → 160 covers 1280 ns in 8 buckets
  std::uint64_t n = 0;
  for (std::size_t i = 0; i < tb.size(); ++i) n += tb[i].n;
  EXPECT_EQ(n, 143U);
}

// at() remembers the last bucket it found; whatever the order of the times, and across
// widening, it must give the bucket the formula gives. Each sample records its own time, so
// a sample counted in the wrong bucket shows as a time outside that bucket's range.
TEST(TimeBuckets, AtGivesTheFormulasBucketForTimesInAnyOrderAndAcrossWidening) {
  struct Times {
    std::vector<Nanos> t;
    void merge(const Times& o) { t.insert(t.end(), o.t.begin(), o.t.end()); }
  };
  std::mt19937_64 rng(7);
  TimeBuckets<Times> tb(5000, 3, 16);
  Nanos now = 5000;
  std::size_t counted = 0;
  for (int i = 0; i < 20000; ++i) {
    now += static_cast<Nanos>(rng() % 5);
    Nanos t = now;
    switch (rng() % 8) {
      case 0: t = now - static_cast<Nanos>(rng() % 40); break;    // out of order
      case 1: t = 4000 + static_cast<Nanos>(rng() % 900); break;  // before the origin
      case 2: t = now + static_cast<Nanos>(rng() % 3); break;     // at a bucket's edge
      case 3:
        // spread() widens too (a record's busy time reaching past the end).
        tb.spread(now, now + static_cast<Nanos>(rng() % 64), [](Times&, double) {});
        break;
      default: break;
    }
    tb.at(t).t.push_back(t);
    ++counted;
  }
  std::size_t seen = 0;
  for (std::size_t i = 0; i < tb.size(); ++i) {
    for (const Nanos t : tb[i].t) {
      ++seen;
      if (t < tb.origin()) {
        EXPECT_EQ(i, 0U) << "time " << t << " before the origin";
        continue;
      }
      EXPECT_GE(t, tb.bucket_start(i)) << "bucket " << i << " width " << tb.width();
      EXPECT_LT(t, tb.bucket_start(i) + tb.width()) << "bucket " << i << " width " << tb.width();
    }
  }
  EXPECT_EQ(seen, counted);
  EXPECT_GT(tb.width(), 3);  // it did widen
}

TEST(TimeBuckets, SpreadSplitsBusyTimeByOverlap) {
  TimeBuckets<Sum> tb(0, 100, 4);
  tb.spread(50, 250, [](Sum& s, double share) { s.v += share * 200.0; });
  EXPECT_DOUBLE_EQ(tb[0].v, 50.0);
  EXPECT_DOUBLE_EQ(tb[1].v, 100.0);
  EXPECT_DOUBLE_EQ(tb[2].v, 50.0);
  EXPECT_DOUBLE_EQ(tb[3].v, 0.0);
  tb.spread(350, 500, [](Sum& s, double share) { s.v += share * 150.0; });  // widens to 200
  EXPECT_EQ(tb.width(), 200);
  EXPECT_DOUBLE_EQ(tb[0].v, 150.0);
  EXPECT_DOUBLE_EQ(tb[1].v, 50.0 + 50.0);
  EXPECT_DOUBLE_EQ(tb[2].v, 100.0);
}

// spread() takes a span inside the bucket at() found last without computing its bucket:
// what it adds, and where, must be what a TimeBuckets that never looked anything up adds.
TEST(TimeBuckets, SpreadInsideTheLastBucketFoundAddsWhatAFreshLookGives) {
  std::mt19937_64 rng(11);
  TimeBuckets<Sum> remembering(1000, 50, 8);
  Nanos now = 1000;
  for (int i = 0; i < 5000; ++i) {
    now += static_cast<Nanos>(rng() % 30);
    const Nanos from = now - static_cast<Nanos>(rng() % 40);
    const Nanos to = from + static_cast<Nanos>(rng() % 60);
    ++remembering.at(now).n;  // as on_record() does before spreading a frame's busy time
    TimeBuckets<Sum> reference(1000, remembering.width(), 8);
    std::vector<std::pair<std::size_t, double>> want;
    std::vector<std::pair<std::size_t, double>> got;
    const auto record_into = [](std::vector<std::pair<std::size_t, double>>& into,
                                const TimeBuckets<Sum>& tb) {
      return [&into, &tb](Sum& s, double share) {
        into.emplace_back(static_cast<std::size_t>(&s - &tb[0]), share);
      };
    };
    reference.spread(from, to, record_into(want, reference));
    remembering.spread(from, to, record_into(got, remembering));
    ASSERT_EQ(got, want) << "from " << from << " to " << to << " width " << remembering.width();
  }
  EXPECT_GT(remembering.width(), 50);  // it widened on the way
}

// ---- TrafficStats over crafted buses --------------------------------------------------

std::vector<std::uint8_t> read_request(std::uint8_t slave, std::uint16_t addr = 0x0010,
                                       std::uint8_t qty = 2) {
  return with_crc({slave, 0x03, static_cast<std::uint8_t>(addr >> 8U),
                   static_cast<std::uint8_t>(addr & 0xFFU), 0x00, qty});
}

std::vector<std::uint8_t> read_response(std::uint8_t slave, std::uint16_t a = 0x1234,
                                        std::uint16_t b = 0x0042) {
  return with_crc({slave, 0x03, 0x04, static_cast<std::uint8_t>(a >> 8U),
                   static_cast<std::uint8_t>(a & 0xFFU), static_cast<std::uint8_t>(b >> 8U),
                   static_cast<std::uint8_t>(b & 0xFFU)});
}

std::vector<std::uint8_t> long_response(std::uint8_t slave, std::uint8_t regs) {
  std::vector<std::uint8_t> body = {slave, 0x03, static_cast<std::uint8_t>(2 * regs)};
  for (std::uint8_t i = 0; i < 2 * regs; ++i) body.push_back(static_cast<std::uint8_t>(i * 7));
  const std::uint16_t crc = crc16(body);
  body.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  body.push_back(static_cast<std::uint8_t>(crc >> 8U));
  return body;
}

std::vector<std::uint8_t> corrupt(std::vector<std::uint8_t> frame) {
  frame[frame.size() - 1] ^= 0x5AU;
  return frame;
}

struct Analysis {
  std::unique_ptr<dissect::DeviceTable> devices = std::make_unique<dissect::DeviceTable>();
  std::unique_ptr<TrafficStats> stats;
  std::vector<Finding> findings;

  [[nodiscard]] const Finding* find(std::string_view key) const {
    for (const auto& f : findings) {
      if (f.key == key) return &f;
    }
    return nullptr;
  }
  [[nodiscard]] double evidence(std::string_view key, std::string_view name) const {
    const Finding* f = find(key);
    if (f == nullptr) return -1;
    for (const auto& e : f->evidence) {
      if (e.name == name) return e.value;
    }
    return -1;
  }
};

// The reads of `bus` (one per byte unless given) through the decoding and the statistics.
Analysis analyse(const BusBuilder& bus, Nanos resolution = kNanosPerMicro,
                 const std::optional<std::vector<Chunk>>& reads = std::nullopt) {
  Analysis a;
  a.stats = std::make_unique<TrafficStats>(a.devices.get());
  // No maps: every slave's values are raw registers.
  dissect::DeviceStage stage(*a.devices, *a.stats, true);
  PipelineOptions o;
  o.line = bus.line();
  o.timing_resolution = resolution;
  o.per_byte_timing = !reads.has_value();
  CaptureInfo info;
  info.source = "crafted";
  info.line = bus.line();
  info.timing_resolution = resolution;
  info.per_byte_timing = o.per_byte_timing;
  DecodePipeline pipeline(o, stage);
  pipeline.start(info);
  for (const Chunk& c : reads ? *reads : bus.per_byte()) pipeline.push(c);
  pipeline.finish();
  a.findings = find_problems(*a.stats);
  return a;
}

// A healthy bus: slaves 1-3 polled in turn, 8-15 ms latency, 50 ms between transactions.
void clean_cycle(BusBuilder& bus, int cycles, std::uint16_t value = 0x1234) {
  for (int c = 0; c < cycles; ++c) {
    for (std::uint8_t s = 1; s <= 3; ++s) {
      bus.add(read_request(s), 50 * kMs);
      bus.add(read_response(s, value, static_cast<std::uint16_t>(c)), (8 + (c * 3 + s) % 8) * kMs);
    }
  }
}

TEST(TrafficStats, CleanBusHasNoFindingsAndExactCounts) {
  BusBuilder bus;
  clean_cycle(bus, 40);
  const Analysis a = analyse(bus);
  for (const auto& f : a.findings) ADD_FAILURE() << f.key << ": " << f.summary;
  const Totals& t = a.stats->totals();
  EXPECT_EQ(t.frames, 240U);
  EXPECT_EQ(t.requests, 120U);
  EXPECT_EQ(t.responses, 120U);
  EXPECT_EQ(t.issues[IssueId::kCrc], 0U);
  EXPECT_EQ(t.noise_bytes, 0U);
  ASSERT_NE(a.stats->slave(2), nullptr);
  EXPECT_EQ(a.stats->slave(2)->requests, 40U);
  EXPECT_EQ(a.stats->slave(2)->latency.count(), 40U);
  EXPECT_EQ(a.stats->slave(4), nullptr);
  // Latencies were laid out as 8..15 ms exactly.
  EXPECT_EQ(a.stats->slave(1)->latency.min(), 8 * kMs);
  EXPECT_EQ(a.stats->slave(1)->latency.max(), 15 * kMs);
}

// Through a USB adapter with a 16 ms latency timer, slave 1's answers (3 ms after the request)
// come in the read that ended their request: their latency is not seen, and is counted apart
// rather than as 0 ms. Slave 2's (40 ms after) start reads of their own: seen, to within the
// timer. Read byte by byte, every latency is seen.
TEST(TrafficStats, ALatencyHiddenInTheRequestsReadIsCountedApartNotAsZero) {
  BusBuilder bus;
  for (int c = 0; c < 20; ++c) {
    bus.add(read_request(1), 100 * kMs);
    bus.add(read_response(1), 3 * kMs);
    bus.add(read_request(2), 100 * kMs);
    bus.add(read_response(2), 40 * kMs);
  }
  const Nanos timer = 16 * kMs;
  const Analysis usb = analyse(bus, timer, bus.usb(timer, 62));
  const SlaveStats* fast = usb.stats->slave(1);
  const SlaveStats* slow = usb.stats->slave(2);
  ASSERT_NE(fast, nullptr);
  ASSERT_NE(slow, nullptr);
  EXPECT_EQ(fast->responses, 20U);
  EXPECT_EQ(fast->latency_unseen, 20U);
  EXPECT_TRUE(fast->latency.empty());
  EXPECT_EQ(slow->latency_unseen, 0U);
  ASSERT_EQ(slow->latency.count(), 20U);
  EXPECT_GE(slow->latency.min(), 40 * kMs - timer);
  EXPECT_LE(slow->latency.max(), 40 * kMs + timer);
  EXPECT_EQ(usb.stats->all_latencies_unseen(), 20U);

  const Analysis per_byte = analyse(bus);
  EXPECT_EQ(per_byte.stats->all_latencies_unseen(), 0U);
  EXPECT_EQ(per_byte.stats->slave(1)->latency.count(), 20U);
  EXPECT_EQ(per_byte.stats->slave(1)->latency.min(), 3 * kMs);
}

TEST(TrafficStats, UtilisationIsBytesTimesCharacterTimeOverDuration) {
  BusBuilder bus;
  clean_cycle(bus, 10);
  const Analysis a = analyse(bus);
  const Totals& t = a.stats->totals();
  EXPECT_EQ(t.bytes, 30U * (8 + 9));
  const double busy = static_cast<double>(t.bytes) * static_cast<double>(bus.line().char_time());
  EXPECT_NEAR(t.utilisation(), busy / static_cast<double>(t.duration()), 1e-12);
  double timeline_busy = 0;
  const auto& tl = a.stats->timeline();
  for (std::size_t i = 0; i < tl.size(); ++i) timeline_busy += tl[i].busy_ns;
  EXPECT_NEAR(timeline_busy, busy, 1.0);
}

TEST(TrafficStats, PollPeriodIsTheMedianIntervalDespiteAMissedPoll) {
  BusBuilder bus;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> jitter(-5, 5);
  for (int c = 0; c < 60; ++c) {
    // One poll of slave 5 per second; poll 30 is skipped (a 2 s interval).
    const Nanos idle = (c == 31 ? 2000 : 1000) * kMs + jitter(rng) * kMs -
                       2 * 9 * bus.line().char_time() - 10 * kMs;
    bus.add(read_request(5, 0x0100, 4), c == 0 ? kMs : idle);
    bus.add(with_crc({5, 0x03, 0x08, 0, 1, 0, 2, 0, 3, 0, 4}), 10 * kMs);
  }
  const Analysis a = analyse(bus);
  const auto& kinds = a.stats->request_kinds();
  ASSERT_EQ(kinds.size(), 1U);
  const auto& [kind, k] = *kinds.begin();
  EXPECT_EQ(kind.slave, 5);
  EXPECT_EQ(kind.function, 3);
  EXPECT_EQ(kind.addr, 0x0100);
  EXPECT_EQ(kind.qty, 4);
  EXPECT_EQ(k.count, 60U);
  EXPECT_EQ(k.responses, 60U);
  EXPECT_NEAR(to_millis(k.period.quantile(0.5)), 1000.0, 20.0);
  EXPECT_GT(to_millis(k.period.max()), 1900.0);
}

TEST(TrafficStats, RawRegisterValuesBecomePointSeries) {
  BusBuilder bus;
  clean_cycle(bus, 5);
  const Analysis a = analyse(bus);
  const auto& points = a.stats->points();
  const auto it = points.find({std::uint8_t{2}, std::string("holding 0x0011")});
  ASSERT_NE(it, points.end());
  EXPECT_EQ(it->second.samples, 5U);
  EXPECT_EQ(it->second.changes, 4U);  // the cycle number 0..4
  EXPECT_EQ(it->second.min, 0.0);
  EXPECT_EQ(it->second.max, 4.0);
  const auto constant = points.find({std::uint8_t{2}, std::string("holding 0x0010")});
  ASSERT_NE(constant, points.end());
  EXPECT_EQ(constant->second.changes, 0U);
  EXPECT_EQ(constant->second.last, 0x1234);
}

TEST(TrafficStats, ReadWriteMultipleGivesWrittenThenReadRegisters) {
  BusBuilder bus;
  // Slave 4 writes 0x00AA, 0x00BB to 0x0003-0x0004, then reads 0x0003-0x0005.
  bus.add(with_crc({4, 0x17, 0, 3, 0, 3, 0, 3, 0, 2, 4, 0, 0xAA, 0, 0xBB}), 50 * kMs);
  bus.add(with_crc({4, 0x17, 6, 0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC}), 10 * kMs);
  const Analysis a = analyse(bus);
  const auto& points = a.stats->points();
  EXPECT_EQ(points.size(), 3U);
  // Written, then read back in the same transaction: the read is the later value.
  const std::vector<std::tuple<const char*, std::uint64_t, double>> expected = {
      {"holding 0x0003", 2, 0x1234}, {"holding 0x0004", 2, 0x5678}, {"holding 0x0005", 1, 0x9ABC}};
  for (const auto& [name, samples, last] : expected) {
    const auto it = points.find({std::uint8_t{4}, std::string(name)});
    ASSERT_NE(it, points.end()) << name;
    EXPECT_EQ(it->second.samples, samples) << name;
    EXPECT_EQ(it->second.last, last) << name;
  }

  const auto& kinds = a.stats->request_kinds();
  ASSERT_EQ(kinds.size(), 1U);
  const auto& [kind, k] = *kinds.begin();
  EXPECT_EQ(kind.function, 0x17);
  EXPECT_TRUE(kind.has_range);  // the range it reads
  EXPECT_EQ(kind.addr, 3);
  EXPECT_EQ(kind.qty, 3);
  EXPECT_EQ(k.responses, 1U);
}

TEST(TrafficStats, ReadWriteMultipleWithAWrongByteCountGivesNoValues) {
  BusBuilder bus;
  // Two registers answer a one-register read: the transaction's byte counts disagree, so
  // the raw source trusts none of it, the write included.
  bus.add(with_crc({4, 0x17, 0, 3, 0, 1, 0, 0x10, 0, 1, 2, 0, 0xAA}), 50 * kMs);
  bus.add(with_crc({4, 0x17, 4, 0x12, 0x34, 0x56, 0x78}), 10 * kMs);
  const Analysis a = analyse(bus);
  EXPECT_TRUE(a.stats->points().empty());
}

TEST(TrafficStats, MaskWriteIsAKindWithoutARangeOrValue) {
  BusBuilder bus;
  bus.add(with_crc({4, 0x16, 0, 4, 0, 0xF2, 0, 0x25}), 50 * kMs);
  bus.add(with_crc({4, 0x16, 0, 4, 0, 0xF2, 0, 0x25}), 10 * kMs);
  const Analysis a = analyse(bus);
  EXPECT_TRUE(a.stats->points().empty());
  const auto& kinds = a.stats->request_kinds();
  ASSERT_EQ(kinds.size(), 1U);
  EXPECT_EQ(kinds.begin()->first.function, 0x16);
  EXPECT_FALSE(kinds.begin()->first.has_range);
}

TEST(Findings, CrcErrorsOnOneSlave) {
  BusBuilder bus;
  for (int c = 0; c < 30; ++c) {
    for (std::uint8_t s = 1; s <= 3; ++s) {
      bus.add(read_request(s), 50 * kMs);
      auto rsp = read_response(s);
      bus.add(s == 2 && c % 4 == 0 ? corrupt(rsp) : rsp, 10 * kMs);
    }
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("crc_errors_one_slave");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->slave, std::uint8_t{2});
  EXPECT_EQ(f->severity, Severity::kError);
  EXPECT_EQ(a.evidence("crc_errors_one_slave", "slave_crc_errors"), 8.0);
  EXPECT_EQ(a.find("crc_errors_spread"), nullptr);
}

TEST(Findings, CrcErrorsOnLongFrames) {
  BusBuilder bus;
  for (int c = 0; c < 24; ++c) {
    for (std::uint8_t s = 1; s <= 3; ++s) {
      const bool big = s == 3 || s == 1;
      bus.add(read_request(s, 0, big ? 40 : 2), 50 * kMs);
      auto rsp = big ? long_response(s, 40) : read_response(s);
      bus.add(big && c % 3 == 0 ? corrupt(rsp) : rsp, 10 * kMs);
    }
  }
  const Analysis a = analyse(bus);
  EXPECT_NE(a.find("crc_errors_long_frames"), nullptr);
  EXPECT_EQ(a.find("crc_errors_one_slave"), nullptr);  // two slaves alike
}

TEST(Findings, ZeroBytesAfterTurnaround) {
  BusBuilder bus;
  clean_cycle(bus, 2);
  for (int c = 0; c < 12; ++c) {
    bus.add(read_request(1), 50 * kMs);
    if (c % 2 == 0) bus.add({0x00}, 5 * kMs);  // slave 1 enables its driver: a false start
    bus.add(read_response(1), 8 * kMs);
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("turnaround_glitches");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(a.evidence("turnaround_glitches", "after_requests"), 6.0);
  EXPECT_EQ(a.evidence("turnaround_glitches", "bytes_00"), 6.0);
  EXPECT_EQ(a.find("noise"), nullptr);  // the glitches are explained
}

TEST(Findings, PausesInsideOneSlavesResponses) {
  BusBuilder bus;
  clean_cycle(bus, 3);
  for (int c = 0; c < 10; ++c) {
    bus.add(read_request(3), 50 * kMs);
    const auto rsp = read_response(3);
    bus.add({rsp.begin(), rsp.begin() + 3}, 10 * kMs);
    bus.add({rsp.begin() + 3, rsp.end()}, 3 * kMs);  // > t1.5 (1.72 ms), < t3.5 (4.01 ms)
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("pauses_in_responses");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->slave, std::uint8_t{3});
  EXPECT_EQ(a.evidence("pauses_in_responses", "responses_with_pause"), 10.0);

  // The same bus seen through timestamps too coarse to show t1.5: no claim.
  const Analysis coarse = analyse(bus, 16 * kMs);
  EXPECT_EQ(coarse.find("pauses_in_responses"), nullptr);
}

TEST(Findings, ResponsesAfterTheMasterMovedOn) {
  BusBuilder bus;
  clean_cycle(bus, 3);
  for (int c = 0; c < 4; ++c) {
    bus.add(read_request(4), 50 * kMs);
    bus.add(read_request(1), 200 * kMs);  // the master gives up on slave 4
    bus.add(read_response(4), 80 * kMs);  // slave 4 answers 300 ms after its request
    bus.add(read_response(1), 20 * kMs);
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("responses_after_next_request");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->slave, std::uint8_t{4});
  EXPECT_EQ(a.evidence("responses_after_next_request", "late_answers"), 4.0);
  EXPECT_EQ(a.find("two_masters"), nullptr);  // one master, one timeout
}

TEST(Findings, RequestsEchoedByTheMastersAdapter) {
  BusBuilder bus;
  clean_cycle(bus, 2);
  for (int c = 0; c < 12; ++c) {
    const auto request = read_request(2);
    bus.add(request, 50 * kMs);
    bus.add(request, kMs / 2);  // the adapter hears itself: the same bytes 0.5 ms later
    bus.add(read_response(2), 9 * kMs);
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("request_echo");
  ASSERT_NE(f, nullptr) << "no request_echo finding";
  EXPECT_EQ(a.evidence("request_echo", "echoed_requests"), 12.0);
  EXPECT_EQ(a.evidence("request_echo", "requests"), 18.0);  // 6 clean + 12 echoed
  EXPECT_NEAR(a.evidence("request_echo", "longest_gap"), 0.5, 0.01);
  // Each first copy was followed by a request before any answer: the tracker's timeout.
  EXPECT_EQ(a.evidence("request_echo", "timeouts_from_echo"), 12.0);
}

TEST(Findings, AMasterRetryingAfterItsTimeoutIsNoEcho) {
  BusBuilder bus;
  clean_cycle(bus, 2);
  for (int c = 0; c < 12; ++c) {
    const auto request = read_request(2);
    bus.add(request, 50 * kMs);
    bus.add(request, 200 * kMs);  // no answer: the master asks again after 200 ms
    bus.add(read_response(2), 9 * kMs);
  }
  EXPECT_EQ(analyse(bus).find("request_echo"), nullptr);
}

TEST(Findings, TwoMastersRequestWhileAnAnswerIsDue) {
  BusBuilder bus;
  clean_cycle(bus, 2);
  // Master 1 polls slave 4 (it answers in 40 ms); master 2's request to slave 1 falls at a
  // different point of each of those transactions.
  for (int c = 0; c < 10; ++c) {
    bus.add(read_request(4), 60 * kMs);
    const Nanos at = (5 + 3 * c) * kMs;  // 5 to 32 ms after the request
    bus.add(read_request(1), at);
    bus.add(read_response(4), 40 * kMs - at);
    bus.add(read_response(1), 6 * kMs);
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("two_masters");
  ASSERT_NE(f, nullptr) << "no two_masters finding";
  EXPECT_EQ(f->slave, std::uint8_t{4});
  EXPECT_EQ(a.evidence("two_masters", "requests_while_answer_due"), 10.0);
  EXPECT_GE(a.evidence("two_masters", "next_request_after_p90"),
            2 * a.evidence("two_masters", "next_request_after_p10"));
}

TEST(Findings, OneMasterWithAShortTimeoutIsNotTwoMasters) {
  BusBuilder bus;
  clean_cycle(bus, 2);
  for (int c = 0; c < 10; ++c) {
    bus.add(read_request(4), 60 * kMs);
    bus.add(read_request(1), 20 * kMs);  // the master gives up after 20 ms, every time
    bus.add(read_response(4), (10 + c) * kMs);
    bus.add(read_response(1), 6 * kMs);
  }
  const Analysis a = analyse(bus);
  EXPECT_NE(a.find("responses_after_next_request"), nullptr);
  EXPECT_EQ(a.find("two_masters"), nullptr);
}

TEST(Findings, TimeoutFitFromTheLatencyDistribution) {
  BusBuilder bus;
  for (int c = 0; c < 200; ++c) {
    bus.add(read_request(7), 50 * kMs);
    // Slave 7 answers in 120 ms, once in 50 polls in 280 ms.
    bus.add(read_response(7), (c % 50 == 0 ? 280 : 120) * kMs);
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("timeout_fit");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->slave, std::uint8_t{7});
  EXPECT_EQ(a.evidence("timeout_fit", "losing_timeout"), 250.0);
  EXPECT_EQ(a.evidence("timeout_fit", "safe_timeout"), 300.0);
  EXPECT_DOUBLE_EQ(a.evidence("timeout_fit", "lost_share"), 2.0);
  EXPECT_NE(
      f->summary.find("250 ms would have lost 2.0% of slave 7's responses; 300 ms loses none"),
      std::string::npos)
      << f->summary;
}

TEST(Findings, SlaveNotResponding) {
  BusBuilder bus;
  clean_cycle(bus, 2);
  for (int c = 0; c < 5; ++c) {
    bus.add(read_request(9), 50 * kMs);
    bus.add(read_request(1), 1100 * kMs);  // after the 1 s response timeout
    bus.add(read_response(1), 10 * kMs);
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("slave_not_responding");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->slave, std::uint8_t{9});
  EXPECT_EQ(a.evidence("slave_not_responding", "timeouts"), 5.0);
  EXPECT_EQ(a.stats->totals().timeouts, 5U);
}

TEST(Findings, ExceptionsForOneRequestKind) {
  BusBuilder bus;
  clean_cycle(bus, 2);
  for (int c = 0; c < 4; ++c) {
    bus.add(read_request(2, 0x0900, 4), 50 * kMs);
    bus.add(with_crc({2, 0x83, 0x02}), 10 * kMs);
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("exceptions_for_request");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(a.evidence("exceptions_for_request", "address"), 0x0900);
  EXPECT_EQ(a.evidence("exceptions_for_request", "exception_code"), 2.0);
  EXPECT_EQ(a.stats->slave(2)->exception_codes.at(2), 4U);
}

TEST(Findings, ResponsesTooSoonAfterTheRequest) {
  BusBuilder bus;
  clean_cycle(bus, 2);
  for (int c = 0; c < 5; ++c) {
    bus.add(read_request(1), 50 * kMs);
    bus.add(read_response(1), 2 * kMs);  // < t3.5
  }
  const Analysis a = analyse(bus);
  const Finding* f = a.find("responses_too_soon");
  ASSERT_NE(f, nullptr) << a.stats->totals().issues[IssueId::kT35];
  EXPECT_EQ(f->slave, std::uint8_t{1});
  EXPECT_EQ(analyse(bus, 16 * kMs).find("responses_too_soon"), nullptr);
}

TEST(Findings, NoiseBursts) {
  BusBuilder bus;
  clean_cycle(bus, 5);
  bus.add({0x13, 0x37, 0xC0, 0xDE, 0x55, 0xAA, 0x42, 0x99, 0x17, 0x71}, 30 * kMs);
  clean_cycle(bus, 5);
  const Analysis a = analyse(bus);
  ASSERT_NE(a.find("noise"), nullptr);
  EXPECT_EQ(a.evidence("noise", "noise_bytes"), 10.0);
}

TEST(Findings, BusNearlyAlwaysBusy) {
  BusBuilder bus;
  // 70 s of back-to-back long reads: the line carries bytes ~95% of the time.
  while (bus.size() < 62000) {
    bus.add(read_request(1, 0, 100), 5 * kMs);
    bus.add(long_response(1, 100), 5 * kMs);
  }
  const Analysis a = analyse(bus);
  ASSERT_NE(a.find("bus_busy"), nullptr);
  EXPECT_GT(a.stats->totals().utilisation(), 0.8);
}

// Line errors need a source that reports them (a logic analyser); records are fed directly.
TEST(Findings, LineErrorsWhereOneSlaveAnswers) {
  TrafficStats stats;
  CaptureInfo info;
  stats.on_capture(info);
  Nanos t = kNanosPerSecond;
  std::int64_t txn = 0;
  auto frame = [&](const std::vector<std::uint8_t>& bytes, Role role, std::uint8_t errors) {
    Record r;
    r.kind = RecordKind::kFrame;
    std::copy(bytes.begin(), bytes.end(), r.storage.begin());
    r.size = static_cast<std::uint16_t>(bytes.size());
    r.crc_ok = crc16_valid(r.bytes());
    r.role = role;
    r.txn = txn;
    r.t_start = t;
    t += static_cast<Nanos>(bytes.size()) * info.line.char_time();
    r.t_end = t;
    r.line_errors = errors;
    t += 20 * kMs;
    stats.on_record(r);
  };
  for (int c = 0; c < 10; ++c) {
    frame(read_request(1), Role::kRequest, 0);
    frame(read_response(1), Role::kResponse, 0);
    frame(read_request(6), Role::kRequest, 0);
    Record noise;
    noise.kind = RecordKind::kNoise;
    noise.storage[0] = 0x3F;
    noise.storage[1] = 0x7E;
    noise.size = 2;
    noise.line_errors = kParityError;
    noise.t_start = t;
    noise.t_end = t + 2 * info.line.char_time();
    t = noise.t_end + 20 * kMs;
    stats.on_record(noise);
  }
  stats.on_finish();
  const auto findings = find_problems(stats);
  const auto it = std::find_if(findings.begin(), findings.end(),
                               [](const Finding& f) { return f.key == "line_errors_one_device"; });
  ASSERT_NE(it, findings.end());
  EXPECT_EQ(it->slave, std::uint8_t{6});
  EXPECT_EQ(stats.totals().parity_errors, 10U);
  EXPECT_GT(stats.totals().valid_frames_between_line_errors, 0U);
}

// ---- Timeouts, damaged requests and turnaround glitches, from records fed by hand --------

// Feeds records straight into TrafficStats, as the tracker would emit them: frames with a
// role and the tracker's issues, noise with the framer's issues, 20 ms apart.
class RecordFeed {
 public:
  RecordFeed() { stats_.on_capture(info_); }

  void frame(const std::vector<std::uint8_t>& bytes, Role role,
             std::initializer_list<IssueId> issues = {}, Nanos silence = 20 * kMs) {
    Record r = make(RecordKind::kFrame, bytes, silence);
    r.crc_ok = crc16_valid(r.bytes());
    if (!r.crc_ok) r.issues.add(IssueId::kCrc);
    for (const IssueId id : issues) r.issues.add(id);
    r.role = role;
    stats_.on_record(r);
  }

  // `line_errors`: LineError bits on its bytes, with the issues the framer gives them.
  void noise(const std::vector<std::uint8_t>& bytes, std::initializer_list<IssueId> issues = {},
             Nanos silence = 20 * kMs, std::uint8_t line_errors = 0) {
    Record r = make(RecordKind::kNoise, bytes, silence);
    r.issues.add(IssueId::kNoiseBytes);
    for (const IssueId id : issues) r.issues.add(id);
    r.line_errors = line_errors;
    if ((line_errors & (kParityError | kFramingError)) != 0) r.issues.add(IssueId::kLineError);
    if ((line_errors & kBreak) != 0) r.issues.add(IssueId::kBreak);
    stats_.on_record(r);
  }

  // The next record's silence happens but its timestamps do not show it (USB batching).
  void blur_next_gap() { blur_next_ = true; }

  // The findings once the capture has ended.
  std::vector<Finding> finish() {
    stats_.on_finish();
    return find_problems(stats_);
  }

  [[nodiscard]] const TrafficStats& stats() const { return stats_; }
  [[nodiscard]] const CaptureInfo& info() const { return info_; }

 private:
  Record make(RecordKind kind, const std::vector<std::uint8_t>& bytes, Nanos silence) {
    Record r;
    r.kind = kind;
    std::copy(bytes.begin(), bytes.end(), r.storage.begin());
    r.size = static_cast<std::uint16_t>(bytes.size());
    r.t_start = t_ + silence;
    r.gap_before = blur_next_ ? kUnknownTime : silence;
    blur_next_ = false;
    r.t_end = r.t_start + static_cast<Nanos>(bytes.size()) * info_.line.char_time();
    t_ = r.t_end;
    return r;
  }

  TrafficStats stats_;
  CaptureInfo info_;
  Nanos t_ = kNanosPerSecond;
  bool blur_next_ = false;
};

const Finding* find_finding(const std::vector<Finding>& findings, std::string_view key,
                            std::optional<std::uint8_t> slave = std::nullopt) {
  for (const auto& f : findings) {
    if (f.key == key && (!slave || f.slave == slave)) return &f;
  }
  return nullptr;
}

double evidence_of(const Finding& f, std::string_view name) {
  for (const auto& e : f.evidence) {
    if (e.name == name) return e.value;
  }
  return -1;
}

TEST(TrafficStats, AnIntactUnansweredRequestIsATimeout) {
  RecordFeed feed;
  feed.frame(read_request(5), Role::kRequest, {IssueId::kTimeout});
  feed.frame(read_request(1), Role::kRequest, {}, 1100 * kMs);
  feed.frame(read_response(1), Role::kResponse);
  feed.finish();
  const TrafficStats& stats = feed.stats();
  ASSERT_NE(stats.slave(5), nullptr);
  EXPECT_EQ(stats.slave(5)->timeouts, 1U);
  EXPECT_EQ(stats.slave(5)->damaged_requests, 0U);
  EXPECT_EQ(stats.totals().timeouts, 1U);
  EXPECT_EQ(stats.totals().damaged_requests, 0U);
}

TEST(TrafficStats, ABadCrcUnansweredRequestIsDamagedNotATimeout) {
  RecordFeed feed;
  feed.frame(corrupt(read_request(5)), Role::kRequest, {IssueId::kTimeout});
  feed.frame(read_request(1), Role::kRequest, {}, 1100 * kMs);
  feed.frame(read_response(1), Role::kResponse);
  feed.finish();
  const TrafficStats& stats = feed.stats();
  ASSERT_NE(stats.slave(5), nullptr);
  EXPECT_EQ(stats.slave(5)->timeouts, 0U);
  EXPECT_EQ(stats.slave(5)->damaged_requests, 1U);
  EXPECT_EQ(stats.slave(5)->requests, 1U);
  EXPECT_EQ(stats.slave(5)->intact_requests, 0U);
  EXPECT_EQ(stats.totals().timeouts, 0U);
  EXPECT_EQ(stats.totals().damaged_requests, 1U);
  // Neither the timeline nor the request kind counts it as a timeout.
  std::uint64_t timeline_timeouts = 0;
  for (std::size_t i = 0; i < stats.timeline().size(); ++i) {
    timeline_timeouts += stats.timeline()[i].timeouts;
  }
  EXPECT_EQ(timeline_timeouts, 0U);
  for (const auto& [kind, k] : stats.request_kinds()) EXPECT_EQ(k.timeouts, 0U);
}

TEST(TrafficStats, LineErrorsOrTruncationMakeARequestDamaged) {
  RecordFeed feed;
  // CRC intact but a parity error on one of its bytes: a slave's UART drops the frame.
  feed.frame(read_request(5), Role::kRequest, {IssueId::kTimeout, IssueId::kLineError});
  feed.frame(read_request(6), Role::kRequest, {IssueId::kTimeout, IssueId::kTruncated});
  feed.frame(read_request(7), Role::kRequest, {IssueId::kTimeout});
  feed.finish();
  const TrafficStats& stats = feed.stats();
  EXPECT_EQ(stats.slave(5)->damaged_requests, 1U);
  EXPECT_EQ(stats.slave(6)->damaged_requests, 1U);
  EXPECT_EQ(stats.slave(7)->timeouts, 1U);
  EXPECT_EQ(stats.totals().timeouts, 1U);
  EXPECT_EQ(stats.totals().damaged_requests, 2U);
}

TEST(TrafficStats, ADamagedFrameOfUnknownRoleReadAsAnUnansweredRequest) {
  RecordFeed feed;
  auto short_request = read_request(5);
  short_request.pop_back();  // a byte lost: fits no length rule, so the tracker gives no role
  feed.frame(read_request(1), Role::kRequest);
  feed.frame(read_response(1), Role::kResponse);
  feed.frame(short_request, Role::kUnknown, {}, 50 * kMs);  // nothing is awaited: the master's
  feed.frame(read_request(2), Role::kRequest, {}, 1100 * kMs);
  feed.frame(read_response(2), Role::kResponse);
  // The same frame answered by slave 5: it read the request intact, nothing is counted.
  feed.frame(short_request, Role::kUnknown, {}, 50 * kMs);
  feed.frame(read_response(5), Role::kResponse, {IssueId::kUnsolicited});
  feed.finish();
  const TrafficStats& stats = feed.stats();
  ASSERT_NE(stats.slave(5), nullptr);
  EXPECT_EQ(stats.slave(5)->damaged_requests, 1U);
  EXPECT_EQ(stats.slave(5)->timeouts, 0U);
  EXPECT_EQ(stats.slave(5)->requests, 0U);  // its role stays unknown
  EXPECT_EQ(stats.totals().damaged_requests, 1U);
  EXPECT_EQ(stats.totals().timeouts, 0U);
}

TEST(TrafficStats, ADamagedFrameWhileAnAnswerIsDueIsNotARequest) {
  RecordFeed feed;
  auto fragment = read_response(3);
  fragment.resize(5);
  ASSERT_FALSE(crc16_valid(fragment));
  // Slave 3's answer, damaged: it comes within the response timeout of the request.
  feed.frame(read_request(3), Role::kRequest, {IssueId::kTimeout});
  feed.frame(fragment, Role::kUnknown, {}, 10 * kMs);
  feed.frame(read_request(3), Role::kRequest, {}, 1100 * kMs);
  feed.frame(read_response(3), Role::kResponse);
  // At the end of the capture a damaged request has no verdict yet, like the tracker's.
  feed.frame(corrupt(read_request(4)), Role::kUnknown, {}, 50 * kMs);
  feed.finish();
  const TrafficStats& stats = feed.stats();
  EXPECT_EQ(stats.totals().damaged_requests, 0U);
  EXPECT_EQ(stats.slave(3)->timeouts, 1U);
}

// The same through the decoder: the tracker's verdicts reach the statistics as they are.
TEST(TrafficStats, DecodedBadCrcAndShortRequestsAreDamagedNotTimeouts) {
  BusBuilder bus;
  clean_cycle(bus, 2);
  bus.add(read_request(5), 50 * kMs);             // intact, never answered: a timeout
  bus.add(corrupt(read_request(5)), 1100 * kMs);  // role request, bad CRC
  bus.add(read_request(1), 1100 * kMs);
  bus.add(read_response(1), 10 * kMs);
  auto short_request = read_request(5);
  short_request.erase(short_request.begin() + 3);  // a byte lost: fits no length, role unknown
  bus.add(short_request, 50 * kMs);
  bus.add(read_request(2), 1100 * kMs);
  bus.add(read_response(2), 10 * kMs);
  const Analysis a = analyse(bus);
  EXPECT_EQ(a.stats->totals().unknown_role, 1U);
  ASSERT_NE(a.stats->slave(5), nullptr);
  EXPECT_EQ(a.stats->slave(5)->timeouts, 1U);
  EXPECT_EQ(a.stats->slave(5)->damaged_requests, 2U);
  EXPECT_EQ(a.stats->totals().timeouts, 1U);
  EXPECT_EQ(a.stats->totals().damaged_requests, 2U);
}

TEST(Findings, DamagedRequestsAreTheWiresFaultNotTheSlaves) {
  RecordFeed feed;
  for (int c = 0; c < 10; ++c) {
    feed.frame(read_request(2), Role::kRequest);
    feed.frame(read_response(2), Role::kResponse);
    // Every other request to slave 4 is damaged and goes unanswered; the rest are answered.
    if (c % 2 == 0) {
      feed.frame(corrupt(read_request(4)), Role::kRequest, {IssueId::kTimeout});
    } else {
      feed.frame(read_request(4), Role::kRequest);
      feed.frame(read_response(4), Role::kResponse);
    }
  }
  const auto findings = feed.finish();
  EXPECT_EQ(feed.stats().slave(4)->damaged_requests, 5U);
  EXPECT_EQ(feed.stats().slave(4)->timeouts, 0U);
  const Finding* f = find_finding(findings, "damaged_requests");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->slave, std::uint8_t{4});
  EXPECT_EQ(evidence_of(*f, "damaged_requests"), 5.0);
  EXPECT_NE(f->cause.find("the wire damaged the master's requests"), std::string::npos);
  EXPECT_NE(f->summary.find("slave 4 ×5"), std::string::npos) << f->summary;
  // The slave answered every request it could read: no timeout finding blames it.
  EXPECT_EQ(find_finding(findings, "slave_not_responding"), nullptr);
  EXPECT_EQ(find_finding(findings, "slave_timeouts"), nullptr);
}

TEST(Findings, NotRespondingIsAShareOfTheIntactRequests) {
  RecordFeed feed;
  // Slave 9 gets 4 intact and 6 damaged requests and answers none: all its intact ones fail.
  for (int c = 0; c < 10; ++c) {
    feed.frame(c < 6 ? corrupt(read_request(9)) : read_request(9), Role::kRequest,
               {IssueId::kTimeout});
  }
  const auto findings = feed.finish();
  const Finding* f = find_finding(findings, "slave_not_responding");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(evidence_of(*f, "timeouts"), 4.0);
  EXPECT_EQ(evidence_of(*f, "intact_requests"), 4.0);
  EXPECT_NE(f->summary.find("left 4 of its 4 intact requests (100%)"), std::string::npos)
      << f->summary;
  ASSERT_NE(find_finding(findings, "damaged_requests"), nullptr);
}

TEST(Findings, TurnaroundGlitchesNameTheirSenderAndAreNotNoise) {
  RecordFeed feed;
  const Nanos within_a_character = feed.info().line.char_time() / 2;
  for (int c = 0; c < 12; ++c) {
    // The master's driver glitches after every request, slave 3's after every other answer.
    feed.frame(read_request(3), Role::kRequest);
    feed.noise({0xFE}, {IssueId::kTurnaroundGlitch}, within_a_character);
    feed.frame(read_response(3), Role::kResponse, {}, 8 * kMs);
    if (c % 2 == 0) feed.noise({0x00}, {IssueId::kTurnaroundGlitch}, within_a_character);
  }
  const auto findings = feed.finish();
  const TrafficStats& stats = feed.stats();
  EXPECT_EQ(stats.totals().noise_records, 18U);
  EXPECT_EQ(stats.totals().turnaround_glitch_records, 18U);
  EXPECT_EQ(stats.totals().turnaround_glitch_bytes, 18U);
  EXPECT_EQ(stats.master_turnaround_glitches(), 12U);
  EXPECT_EQ(stats.slave(3)->turnaround_glitches_sent, 6U);
  EXPECT_EQ(stats.unexplained_noise_records(), 0U);
  EXPECT_EQ(stats.unexplained_noise_bytes(), 0U);

  const Finding* master = find_finding(findings, "turnaround_glitch", std::nullopt);
  ASSERT_NE(master, nullptr);
  EXPECT_FALSE(master->slave.has_value());
  EXPECT_EQ(evidence_of(*master, "glitches"), 12.0);
  EXPECT_EQ(evidence_of(*master, "requests"), 12.0);
  EXPECT_EQ(master->cause,
            "the master's RS-485 driver/transceiver glitches at turnaround (driver-enable "
            "timing or missing bias/termination)");
  const Finding* slave = find_finding(findings, "turnaround_glitch", std::uint8_t{3});
  ASSERT_NE(slave, nullptr);
  EXPECT_EQ(evidence_of(*slave, "glitches"), 6.0);
  EXPECT_EQ(evidence_of(*slave, "responses"), 12.0);
  EXPECT_NE(slave->cause.find("slave 3's RS-485 driver/transceiver"), std::string::npos);
  // Flagged glitches feed neither the interference finding nor the 0x00/0xFF heuristic.
  EXPECT_EQ(find_finding(findings, "noise"), nullptr);
  EXPECT_EQ(find_finding(findings, "turnaround_glitches"), nullptr);
  EXPECT_EQ(stats.glitch_bytes_00(), 0U);
}

TEST(Findings, NoiseFindingCountsBytesAndStretchesOverTheSameRecords) {
  RecordFeed feed;
  for (int c = 0; c < 46; ++c) {
    feed.frame(read_request(1), Role::kRequest);
    feed.noise({0x00}, {}, 2 * kMs);  // a 0x00 after the request: a turnaround glitch
    feed.frame(read_response(1), Role::kResponse, {}, 8 * kMs);
    if (c < 10) feed.noise({0x13, 0x37, 0x42});  // interference between transactions
  }
  const auto findings = feed.finish();
  const TrafficStats& stats = feed.stats();
  EXPECT_EQ(stats.totals().noise_records, 56U);
  EXPECT_EQ(stats.totals().noise_bytes, 76U);
  EXPECT_EQ(stats.unexplained_noise_records(), 10U);
  EXPECT_EQ(stats.unexplained_noise_bytes(), 30U);
  const Finding* f = find_finding(findings, "noise");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(evidence_of(*f, "noise_bytes"), 30.0);
  EXPECT_EQ(evidence_of(*f, "noise_records"), 10.0);
  EXPECT_NE(f->summary.find("30 bytes"), std::string::npos) << f->summary;
  EXPECT_NE(f->summary.find("in 10 stretches"), std::string::npos) << f->summary;
  EXPECT_NE(f->summary.find("of 76 noise bytes in 56 records; the other 46 records are "
                            "turnaround glitches"),
            std::string::npos)
      << f->summary;
  EXPECT_EQ(evidence_of(*find_finding(findings, "turnaround_glitches"), "glitches"), 46.0);
}

// ---- Timing across turnaround glitches -------------------------------------------------

// 9600 8E1, the feed's line: 11 bits a character.
constexpr Nanos kCharTime = 1'145'833;

TEST(TrafficStats, MasterTurnaroundIsMeasuredAcrossAFlaggedGlitch) {
  RecordFeed feed;
  ASSERT_EQ(feed.info().line.char_time(), kCharTime);
  for (int c = 0; c < 4; ++c) {
    feed.frame(read_request(1), Role::kRequest, {}, c == 0 ? 20 * kMs : 4 * kMs);
    feed.frame(read_response(1), Role::kResponse, {}, 3 * kMs);
    // 0.1 ms after the response its sender's driver lets go: one byte of glitch.
    feed.noise({0xFE}, {IssueId::kTurnaroundGlitch}, 100 * kNanosPerMicro);
  }
  feed.frame(read_request(1), Role::kRequest, {}, 4 * kMs);
  feed.finish();
  const LogHistogram& h = feed.stats().master_turnaround();
  // From the response's end: 0.1 ms of silence, the glitch's character, 4 ms of silence.
  const Nanos expected = 100 * kNanosPerMicro + kCharTime + 4 * kMs;  // 5.245833 ms
  EXPECT_EQ(expected, 5'245'833);
  EXPECT_EQ(h.count(), 4U);
  EXPECT_EQ(h.min(), expected);
  EXPECT_EQ(h.max(), expected);
}

TEST(TrafficStats, MasterTurnaroundIsMeasuredAcrossAZeroByteAfterTheResponse) {
  RecordFeed feed;
  feed.frame(read_request(2), Role::kRequest);
  feed.frame(read_response(2), Role::kResponse, {}, 3 * kMs);
  feed.noise({0x00}, {}, 2 * kMs);  // not flagged (too late), but a 0x00 after a turnaround
  feed.frame(read_request(2), Role::kRequest, {}, 5 * kMs);
  feed.finish();
  const LogHistogram& h = feed.stats().master_turnaround();
  ASSERT_EQ(h.count(), 1U);
  EXPECT_EQ(h.min(), 2 * kMs + kCharTime + 5 * kMs);  // 8.145833 ms
  EXPECT_EQ(feed.stats().glitches_after_response(), 1U);
}

TEST(TrafficStats, OtherNoiseOrABlurredGapStillEndsTheTurnaround) {
  RecordFeed feed;
  // Interference between the response and the next request: not the master's turnaround.
  feed.frame(read_request(3), Role::kRequest);
  feed.frame(read_response(3), Role::kResponse, {}, 3 * kMs);
  feed.noise({0x13, 0x37, 0x42}, {}, 2 * kMs);
  feed.frame(read_request(3), Role::kRequest, {}, 5 * kMs);
  // A glitch whose gap the timestamps blur: the span across it is unknown.
  feed.frame(read_response(3), Role::kResponse, {}, 3 * kMs);
  feed.blur_next_gap();
  feed.noise({0xFE}, {IssueId::kTurnaroundGlitch}, 100 * kNanosPerMicro);
  feed.frame(read_request(3), Role::kRequest, {}, 5 * kMs);
  // A plain turnaround is still measured, from the gap alone.
  feed.frame(read_response(3), Role::kResponse, {}, 3 * kMs);
  feed.frame(read_request(3), Role::kRequest, {}, 6 * kMs);
  feed.finish();
  const LogHistogram& h = feed.stats().master_turnaround();
  ASSERT_EQ(h.count(), 1U);
  EXPECT_EQ(h.min(), 6 * kMs);
}

// Through the framer: the glitch is flagged there and t3.5 and the master's turnaround are
// both measured across it, as on the same traffic without the glitch.
TEST(TrafficStats, GlitchesDoNotChangeTheTimingOfTheTrafficAroundThem) {
  auto traffic = [](bool glitches) {
    BusBuilder bus;
    Nanos idle = 20 * kMs;
    for (int c = 0; c < 5; ++c) {
      bus.add(read_request(1), idle);
      if (glitches) bus.add({0x00}, 20 * kNanosPerMicro);
      // 3 ms after the request's end, glitch or not: less than t3.5 (4.010 ms).
      bus.add(read_response(1), glitches ? 3 * kMs - 20 * kNanosPerMicro - kCharTime : 3 * kMs);
      if (glitches) bus.add({0xFE}, 150 * kNanosPerMicro);
      idle = glitches ? 5 * kMs - 150 * kNanosPerMicro - kCharTime : 5 * kMs;
    }
    return analyse(bus);
  };
  const Analysis clean = traffic(false);
  const Analysis wire = traffic(true);
  EXPECT_EQ(wire.stats->totals().turnaround_glitch_records, 10U);
  for (const Analysis* a : {&clean, &wire}) {
    const LogHistogram& h = a->stats->master_turnaround();
    EXPECT_EQ(h.count(), 4U);
    EXPECT_EQ(h.min(), 5 * kMs);
    EXPECT_EQ(h.max(), 5 * kMs);
    const LogHistogram latency = a->stats->all_latencies();
    EXPECT_EQ(latency.count(), 5U);
    EXPECT_EQ(latency.min(), 3 * kMs);
    EXPECT_EQ(latency.max(), 3 * kMs);
    EXPECT_EQ(a->stats->slave(1)->t35_responses, 5U);
    EXPECT_NE(a->find("responses_too_soon"), nullptr);
  }
}

// ---- Line errors on turnaround glitches -------------------------------------------------

// The sigrok wizmodbus bus capture in small: after each request the master's driver lets go
// and the undriven bus reads as a 0x00 with a framing error until the slave drives it; after
// each answer the slave's driver leaves a clean 0xFE.
TEST(Findings, FramingErrorsOnTurnaroundGlitchesAreTheFloatingBusNotADevice) {
  RecordFeed feed;
  const Nanos within_a_character = feed.info().line.char_time() / 2;
  for (int c = 0; c < 10; ++c) {
    feed.frame(read_request(1), Role::kRequest, {}, 4 * kMs);
    feed.noise({0x00}, {IssueId::kTurnaroundGlitch}, 20 * kNanosPerMicro, kFramingError);
    feed.frame(read_response(1), Role::kResponse, {}, 2 * kMs);
    feed.noise({0xFE}, {IssueId::kTurnaroundGlitch}, within_a_character);
  }
  const auto findings = feed.finish();
  const TrafficStats& stats = feed.stats();
  const Totals& t = stats.totals();
  // The totals still show every line error the wire had...
  EXPECT_EQ(t.line_error_records, 10U);
  EXPECT_EQ(t.framing_errors, 10U);
  // ...all of them on glitches, where they blame no slave.
  EXPECT_EQ(t.glitch_line_errors.records, 10U);
  EXPECT_EQ(t.glitch_line_errors.framing, 10U);
  EXPECT_EQ(t.line_errors_beyond_glitches().records, 0U);
  EXPECT_EQ(t.turnaround_glitch_line_errors, 10U);
  EXPECT_EQ(stats.master_turnaround_glitch_line_errors(), 10U);
  EXPECT_EQ(stats.slave(1)->turnaround_glitch_line_errors, 0U);
  EXPECT_EQ(stats.slave(1)->line_errors, 0U);
  EXPECT_EQ(stats.line_errors_unattributed(), 0U);
  EXPECT_EQ(t.valid_frames_between_line_errors, 0U);
  EXPECT_EQ(find_finding(findings, "line_errors_one_device"), nullptr);
  EXPECT_EQ(find_finding(findings, "line_errors"), nullptr);

  const Finding* master = find_finding(findings, "turnaround_glitch", std::nullopt);
  ASSERT_NE(master, nullptr);
  EXPECT_FALSE(master->slave.has_value());
  EXPECT_EQ(evidence_of(*master, "glitches"), 10.0);
  EXPECT_EQ(evidence_of(*master, "line_errors"), 10.0);
  EXPECT_NE(master->summary.find("; 10 with a framing error or break"), std::string::npos)
      << master->summary;
  EXPECT_EQ(master->cause,
            "a framing error or break at turnaround means the bus floats when the master's "
            "driver lets go: nobody holds the line idle, so the fail-safe bias resistors are "
            "missing (or too weak); the master's driver-enable timing may add to it");
  // The slave's own glitches were clean: its driver, as before.
  const Finding* slave = find_finding(findings, "turnaround_glitch", std::uint8_t{1});
  ASSERT_NE(slave, nullptr);
  EXPECT_EQ(evidence_of(*slave, "line_errors"), 0.0);
  EXPECT_EQ(slave->cause,
            "slave 1's RS-485 driver/transceiver glitches at turnaround (driver-enable timing or "
            "missing bias/termination)");
  // The master's turnaround is timed across the slave's glitch, from the response's end: half
  // a character, the glitch's character, then 4 ms of silence.
  const LogHistogram& h = stats.master_turnaround();
  EXPECT_EQ(h.count(), 9U);
  EXPECT_EQ(h.min(), within_a_character + kCharTime + 4 * kMs);
}

// A device really set to other line settings is still found beside glitch line errors, and
// its numbers leave the glitches out.
TEST(Findings, DeviceLineErrorsAreCountedWithoutTheGlitchOnes) {
  RecordFeed feed;
  for (int c = 0; c < 10; ++c) {
    feed.frame(read_request(1), Role::kRequest);
    feed.noise({0x00}, {IssueId::kTurnaroundGlitch}, 20 * kNanosPerMicro, kFramingError);
    feed.frame(read_response(1), Role::kResponse, {}, 3 * kMs);
    // Slave 6 answers at another parity: its answer is noise with parity errors.
    feed.frame(read_request(6), Role::kRequest, {IssueId::kTimeout});
    feed.noise({0x3F, 0x7E, 0x11}, {}, 5 * kMs, kParityError);
  }
  const auto findings = feed.finish();
  const Totals& t = feed.stats().totals();
  EXPECT_EQ(t.line_error_records, 20U);
  EXPECT_EQ(t.line_errors_beyond_glitches().records, 10U);
  EXPECT_EQ(t.line_errors_beyond_glitches().parity, 10U);
  EXPECT_EQ(t.line_errors_beyond_glitches().framing, 0U);
  EXPECT_EQ(feed.stats().slave(6)->line_errors, 10U);
  EXPECT_EQ(feed.stats().slave(1)->line_errors, 0U);
  // Valid frames between the first and the last device line error: 9 cycles of 3 frames.
  EXPECT_EQ(t.valid_frames_between_line_errors, 27U);
  const Finding* f = find_finding(findings, "line_errors_one_device");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->slave, std::uint8_t{6});
  EXPECT_EQ(evidence_of(*f, "slave_line_errors"), 10.0);
  EXPECT_EQ(evidence_of(*f, "line_error_records"), 10.0);
  EXPECT_NE(f->summary.find("10 of 10 records with parity/framing errors (100%) fall where "
                            "slave 6 answers, with 27 valid frames in between (besides 10 on "
                            "turnaround glitches)"),
            std::string::npos)
      << f->summary;
}

// The framer's glitches and the 0x00/0xFF heuristic share out the glitch records: each record
// is in one finding only, and together with the other noise they make up the noise records.
TEST(Findings, BothTurnaroundGlitchFindingsCountDisjointRecords) {
  RecordFeed feed;
  for (int c = 0; c < 8; ++c) {
    feed.frame(read_request(2), Role::kRequest, {}, 6 * kMs);
    feed.noise({0x00}, {IssueId::kTurnaroundGlitch}, 20 * kNanosPerMicro, kFramingError);
    feed.frame(read_response(2), Role::kResponse, {}, 3 * kMs);
    // A late 0xFF after the answer, which the framer does not flag; every other one framed
    // badly.
    feed.noise({0xFF}, {}, 2 * kMs, c % 2 == 0 ? kFramingError : 0);
    if (c < 2) feed.noise({0x13, 0x37, 0x42}, {}, 10 * kMs);  // interference
  }
  const auto findings = feed.finish();
  const TrafficStats& stats = feed.stats();
  const Totals& t = stats.totals();
  EXPECT_EQ(t.noise_records, 18U);
  EXPECT_EQ(t.turnaround_glitch_records, 8U);
  EXPECT_EQ(stats.glitches_after_response(), 8U);
  EXPECT_EQ(stats.unexplained_noise_records(), 2U);
  EXPECT_EQ(t.turnaround_glitch_records + stats.glitches_after_response() +
                stats.unexplained_noise_records(),
            t.noise_records);
  EXPECT_EQ(t.glitch_line_errors.records, 12U);
  EXPECT_EQ(t.turnaround_glitch_line_errors, 8U);
  EXPECT_EQ(stats.glitches_after_turnaround_line_errors(), 4U);

  const Finding* flagged = find_finding(findings, "turnaround_glitch");
  ASSERT_NE(flagged, nullptr);
  EXPECT_EQ(evidence_of(*flagged, "glitches"), 8.0);
  EXPECT_EQ(evidence_of(*flagged, "line_errors"), 8.0);
  const Finding* heuristic = find_finding(findings, "turnaround_glitches");
  ASSERT_NE(heuristic, nullptr);
  EXPECT_EQ(evidence_of(*heuristic, "glitches"), 8.0);
  EXPECT_EQ(evidence_of(*heuristic, "after_responses"), 8.0);
  EXPECT_EQ(evidence_of(*heuristic, "bytes_ff"), 8.0);
  EXPECT_EQ(evidence_of(*heuristic, "line_errors"), 4.0);
  EXPECT_NE(heuristic->summary.find("besides the 8 lone bytes right after a frame "
                                    "(turnaround_glitch), not counted here"),
            std::string::npos)
      << heuristic->summary;
  EXPECT_NE(heuristic->cause.find("4 of them carry a framing error or break"), std::string::npos)
      << heuristic->cause;
  // No line error here is a device's; the interference is the noise finding's alone.
  EXPECT_EQ(find_finding(findings, "line_errors_one_device"), nullptr);
  EXPECT_EQ(find_finding(findings, "line_errors"), nullptr);
  const Finding* noise = find_finding(findings, "noise");
  ASSERT_EQ(noise, nullptr) << "6 bytes are below the noise finding's 8";
}

}  // namespace
}  // namespace rtu
