// Throughput of the hot stages one at a time, so that an optimisation's gain can be measured
// before and after on the stage it touches: time parsing, CRC, text hex reading, the line
// check's survey of byte spacings, the framer (on polling and on random frames),
// the tracker, the statistics, PDU decoding, the statistics' histograms, the report's whole
// pass after the reader, and JSON writing.
// Run: build/tools/bench/rtuscope_bench --benchmark_filter=Stage
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "bus_builder.hpp"
#include "capture/decimal_time.hpp"
#include "capture/open_capture.hpp"
#include "core/crc16.hpp"
#include "core/json_writer.hpp"
#include "core/output_stream.hpp"
#include "dissect/device_stage.hpp"
#include "dissect/device_table.hpp"
#include "framing/framer.hpp"
#include "framing/line_check.hpp"
#include "modbus/pdu.hpp"
#include "pairing/transaction_tracker.hpp"
#include "pipeline/decode_pipeline.hpp"
#include "report/jsonl_writer.hpp"
#include "report/log_histogram.hpp"
#include "report/traffic_stats.hpp"

namespace rtu {
namespace {

// Four slaves polled for three registers each, 20 ms apart, answered 5 ms later.
test::BusBuilder polling(int transactions) {
  test::BusBuilder bus;
  for (int i = 0; i < transactions; ++i) {
    const auto slave = static_cast<std::uint8_t>(1 + i % 4);
    bus.add(test::with_crc({slave, 0x03, 0x00, 0x32, 0x00, 0x03}), 20 * kNanosPerMilli);
    bus.add(test::with_crc(
                {slave, 0x03, 0x06, 0xEA, 0x60, 0xC3, 0x50, 0xDB, static_cast<std::uint8_t>(i)}),
            5 * kNanosPerMilli);
  }
  return bus;
}

// The records a bus decodes to, kept (with their requests) for stages after pairing.
class Keep final : public RecordSink {
 public:
  void on_record(Record& r) override { records.push_back(r); }
  std::vector<Record> records;
};

void BM_StageDecimalSeconds(benchmark::State& state) {
  std::vector<std::string> stamps;
  for (int i = 0; i < 1000; ++i) stamps.push_back(fmt::format("1700000{:03d}.{:06d}", i, i * 997));
  for (auto _ : state) {
    for (const auto& s : stamps) benchmark::DoNotOptimize(parse_decimal_seconds(s, false));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(stamps.size()));
}

void BM_StageCrc16(benchmark::State& state) {
  std::vector<std::uint8_t> frame(static_cast<std::size_t>(state.range(0)));
  for (std::size_t i = 0; i < frame.size(); ++i) frame[i] = static_cast<std::uint8_t>(i * 31);
  for (auto _ : state) benchmark::DoNotOptimize(crc16(frame));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * state.range(0));
}

// A per-byte text hex capture on disk, read through its reader with nothing after it.
void BM_StageTextHexReader(benchmark::State& state) {
  const auto bus = polling(4000);
  const std::string path =
      (std::filesystem::temp_directory_path() / fmt::format("rtuscope-bench-{}.hex", ::getpid()))
          .string();
  {
    std::ofstream out(path);
    out << "# baud=9600 parity=E stop=1\n";
    for (const Chunk& c : bus.per_byte()) {
      out << fmt::format("{}.{:09d} {:02X}\n", c.t_end / kNanosPerSecond, c.t_end % kNanosPerSecond,
                         c.bytes[0]);
    }
  }
  class Null final : public CaptureConsumer {
   public:
    void on_chunk(const Chunk& c) override { benchmark::DoNotOptimize(c.t_end); }
    void on_frame(std::span<const std::uint8_t>, Nanos, std::uint64_t) override {}
    void on_noise(std::span<const std::uint8_t>, Nanos, std::uint64_t) override {}
    void on_end(Nanos) override {}
  } null;
  std::int64_t lines = 0;
  for (auto _ : state) {
    auto reader = open_capture(path, [](std::string_view) {});
    while (reader->read(null)) ++lines;
  }
  std::remove(path.c_str());
  state.SetItemsProcessed(lines);
}

// The line check's survey of a per-byte capture's reads (every byte's spacing into its
// histogram), as the reading thread of a per-byte replay does it alongside the parsing.
void BM_StageLineCheck(benchmark::State& state) {
  const auto bus = polling(4000);
  const ByteReads reads = bus.byte_reads();
  for (auto _ : state) {
    LineCheck check;
    check.add(reads);
    benchmark::DoNotOptimize(check.byte_spacing(0));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(reads.size()));
}

// A framer over `chunks` from the start, once per iteration; the frames it finds are the
// items.
void run_framer(benchmark::State& state, const FramerConfig& config,
                const std::vector<Chunk>& chunks) {
  class Count final : public RecordSink {
   public:
    void on_record(Record& r) override { frames += r.kind == RecordKind::kFrame ? 1 : 0; }
    std::int64_t frames = 0;
  } count;
  for (auto _ : state) {
    Framer framer(config, count);
    for (const Chunk& c : chunks) framer.push(c);
    framer.finish();
  }
  state.SetItemsProcessed(count.frames);
}

// The framer alone on the polling traffic's reads (arg 0: one byte a read, 1: 16 ms USB
// batches): what a replay's reading thread spends on finding frames.
void BM_StageFramer(benchmark::State& state) {
  const bool batched = state.range(0) != 0;
  const auto bus = polling(2000);
  const auto chunks = batched ? bus.batched(16 * kNanosPerMilli) : bus.per_byte();
  FramerConfig config;
  config.line = bus.line();
  config.resolution = batched ? 16 * kNanosPerMilli : kNanosPerMicro;
  run_framer(state, config, chunks);
}

// CRC-valid frames of a random slave (0-255), a random function code (0-255) and 0-60 random
// data bytes, four characters apart: traffic that no length rule frames, where every byte
// may start a frame (tools/bench/random_frames.py writes the same kind for compare.sh).
test::BusBuilder random_frames(int frames) {
  test::BusBuilder bus;
  std::mt19937 random(1);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> data_bytes(0, 60);
  const Nanos pause = 4 * bus.line().char_time();
  for (int i = 0; i < frames; ++i) {
    std::vector<std::uint8_t> frame(2 + static_cast<std::size_t>(data_bytes(random)));
    for (auto& b : frame) b = static_cast<std::uint8_t>(byte(random));
    bus.add(test::with_crc(std::move(frame)), pause);
  }
  return bus;
}

// The framer alone on random frames (arg 0: one byte a read, 1: a read per frame), the
// traffic that costs it the most per byte.
void BM_StageFramerRandom(benchmark::State& state) {
  const bool per_frame = state.range(0) != 0;
  const auto bus = random_frames(2000);
  const auto chunks = per_frame ? bus.per_add() : bus.per_byte();
  FramerConfig config;
  config.line = bus.line();
  config.resolution = kNanosPerMicro;
  run_framer(state, config, chunks);
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bus.size()));
}

// The records the framer makes of the polling traffic, before pairing.
std::vector<Record> framed_polling(int transactions) {
  const auto bus = polling(transactions);
  FramerConfig config;
  config.line = bus.line();
  config.resolution = kNanosPerMicro;
  Keep kept;
  Framer framer(config, kept);
  for (const Chunk& c : bus.per_byte()) framer.push(c);
  framer.finish();
  return kept.records;
}

// The records the whole pipeline makes of the polling traffic, paired. The requests their
// responses pointed at went with the tracker: each response points at the request kept
// before it instead (so the vector must be moved, never copied).
std::vector<Record> paired_polling(int transactions) {
  Keep kept;
  {
    PipelineOptions options;
    options.timing_resolution = kNanosPerMicro;
    DecodePipeline pipeline(options, kept);
    for (const auto& c : polling(transactions).per_byte()) pipeline.push(c);
    pipeline.finish();
  }
  const Record* last_request = nullptr;
  for (Record& r : kept.records) {
    if (r.role == Role::kRequest) last_request = &r;
    r.request = r.role == Role::kResponse ? last_request : nullptr;
  }
  return std::move(kept.records);
}

// The transaction tracker alone: roles, pairing, timeouts and the PDU checks it runs.
void BM_StageTracker(benchmark::State& state) {
  const std::vector<Record> framed = framed_polling(2000);
  class Null final : public RecordSink {
   public:
    void on_record(Record& r) override { benchmark::DoNotOptimize(r.txn); }
  } null;
  Record scratch;
  for (auto _ : state) {
    TransactionTracker tracker(TrackerConfig{}, null);
    for (const Record& r : framed) {
      scratch = r;
      tracker.on_record(scratch);
    }
    tracker.on_finish();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(framed.size()));
}

// The report's statistics alone, on paired records (each response pointing at its request)
// with no device map: counts, latencies, poll periods and the raw register series.
void BM_StageStatistics(benchmark::State& state) {
  std::vector<Record> records = paired_polling(2000);
  for (auto _ : state) {
    TrafficStats stats;
    dissect::DeviceTable table;
    dissect::DeviceStage stage(table, stats, true);
    for (Record& r : records) stage.on_record(r);
    benchmark::DoNotOptimize(stats.totals().frames);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(records.size()));
}

void BM_StageDecodePdu(benchmark::State& state) {
  const std::vector<Record> records = paired_polling(500);
  for (auto _ : state) {
    for (const Record& r : records) benchmark::DoNotOptimize(decode_pdu(r, r.role));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(records.size()));
}

// Framing and pairing, then the device stage (raw register values) and the statistics:
// the report's whole decoding pass after the reader.
void BM_StageReportPass(benchmark::State& state) {
  const auto bus = polling(2000);
  const auto chunks = bus.batched(16 * kNanosPerMilli);
  PipelineOptions options;
  options.line = bus.line();
  options.timing_resolution = 16 * kNanosPerMilli;
  for (auto _ : state) {
    TrafficStats stats;
    dissect::DeviceTable table;
    dissect::DeviceStage stage(table, stats, true);
    DecodePipeline pipeline(options, stage);
    for (const auto& c : chunks) pipeline.push(c);
    pipeline.finish();
    benchmark::DoNotOptimize(stats.totals().frames);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 4000);
}

// The latency and period histograms the statistics add to several times per transaction:
// values spread like a bus's (microseconds to seconds).
void BM_StageLogHistogram(benchmark::State& state) {
  std::vector<Nanos> values;
  Nanos v = 7919;
  for (int i = 0; i < 4096; ++i) {
    v = (v * 48271) % 2'147'483'647;
    values.push_back(v % (kNanosPerSecond / (1 + i % 1000)));
  }
  LogHistogram histogram;
  for (auto _ : state) {
    for (const Nanos x : values) histogram.add(x);
  }
  benchmark::DoNotOptimize(histogram.count());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(values.size()));
}

void BM_StageJsonWriter(benchmark::State& state) {
  fmt::memory_buffer out;
  const std::vector<std::uint8_t> adu = {0x01, 0x03, 0x06, 0xEA, 0x60, 0xC3, 0x50, 0xDB, 0x12};
  for (auto _ : state) {
    out.clear();
    JsonWriter json(out);
    json.begin_object();
    json.field("t", std::int64_t{1'700'000'000'123'456'789});
    json.field("kind", "frame");
    json.field("slave", 1U);
    json.field("fc", 3U);
    json.key("hex");
    json.hex(adu);
    json.key("value");
    json.value_fixed(229.8, 1);
    json.end_object();
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

// Whole JSONL records as `decode --format jsonl` writes them (to /dev/null): times, hex,
// function names, the PDU's fields and the register values.
void BM_StageJsonlRecord(benchmark::State& state) {
  std::vector<Record> records = paired_polling(2000);
  OutputStream out("/dev/null");
  JsonlWriter writer(out);
  for (auto _ : state) {
    for (Record& r : records) writer.on_record(r);
  }
  writer.on_finish();
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(records.size()));
}

BENCHMARK(BM_StageDecimalSeconds);
BENCHMARK(BM_StageCrc16)->Arg(8)->Arg(256);
BENCHMARK(BM_StageTextHexReader)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StageLineCheck)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StageFramer)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StageFramerRandom)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StageTracker)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StageStatistics)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StageDecodePdu);
BENCHMARK(BM_StageReportPass)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StageLogHistogram);
BENCHMARK(BM_StageJsonWriter);
BENCHMARK(BM_StageJsonlRecord);

}  // namespace
}  // namespace rtu
