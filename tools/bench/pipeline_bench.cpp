// Throughput of the decode path: framer + tracker (+ JSONL rendering), on synthetic polling
// traffic, with per-byte timestamps and with 16 ms USB batching.
#include <benchmark/benchmark.h>

#include "bus_builder.hpp"
#include "pipeline/decode_pipeline.hpp"
#include "report/jsonl_writer.hpp"

namespace rtu {
namespace {

class NullSink : public RecordSink {
 public:
  void on_record(Record& record) override { benchmark::DoNotOptimize(record.size); }
};

test::BusBuilder polling_traffic(int transactions) {
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

void run_pipeline(benchmark::State& state, bool batched, bool render_json) {
  const auto bus = polling_traffic(2000);
  const auto chunks = batched ? bus.batched(16 * kNanosPerMilli) : bus.per_byte();
  PipelineOptions options;
  options.line = bus.line();
  options.timing_resolution = batched ? 16 * kNanosPerMilli : kNanosPerMicro;
  for (auto _ : state) {
    NullSink null_sink;
    OutputStream devnull("/dev/null");
    JsonlWriter json(devnull);
    RecordSink& sink = render_json ? static_cast<RecordSink&>(json) : null_sink;
    DecodePipeline pipeline(options, sink);
    for (const auto& c : chunks) pipeline.push(c);
    pipeline.finish();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(bus.size()));
}

void BM_FramePairPerByte(benchmark::State& s) {
  run_pipeline(s, false, false);
}
void BM_FramePairUsbBatched(benchmark::State& s) {
  run_pipeline(s, true, false);
}
void BM_FramePairJsonUsbBatched(benchmark::State& s) {
  run_pipeline(s, true, true);
}

BENCHMARK(BM_FramePairPerByte)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FramePairUsbBatched)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FramePairJsonUsbBatched)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rtu
