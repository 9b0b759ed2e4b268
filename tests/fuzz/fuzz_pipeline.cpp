// Fuzz target for the whole decode path: chunks → framer → tracker → JSONL and text.
// The input is split into chunks with fuzzer-chosen sizes and time steps, so the framer
// sees every mix of batched and per-byte timing. Oracle: every input byte leaves in exactly
// one record, no record exceeds 256 bytes, records leave in time order.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "pipeline/decode_pipeline.hpp"
#include "report/jsonl_writer.hpp"
#include "report/text_writer.hpp"

namespace {

class CheckingSink : public rtu::RecordSink {
 public:
  CheckingSink(rtu::RecordSink& json, rtu::RecordSink& text) : json_(json), text_(text) {}
  void on_record(rtu::Record& record) override {
    if (record.size == 0 || record.size > rtu::kMaxAdu) std::abort();
    if (record.t_end < record.t_start) std::abort();
    if (last_start_ != rtu::kUnknownTime && record.t_start < last_start_) std::abort();
    last_start_ = record.t_start;
    bytes += record.size;
    json_.on_record(record);
    text_.on_record(record);
  }
  std::size_t bytes = 0;

 private:
  rtu::RecordSink& json_;
  rtu::RecordSink& text_;
  rtu::Nanos last_start_ = rtu::kUnknownTime;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  rtu::PipelineOptions options;
  options.line.baud = (data[0] & 1U) != 0 ? 9600 : 115200;
  options.timing_resolution = (data[0] & 2U) != 0 ? 16 * rtu::kNanosPerMilli : rtu::kNanosPerMicro;
  options.response_timeout = 100 * rtu::kNanosPerMilli;
  static rtu::OutputStream devnull("/dev/null");
  rtu::JsonlWriter json(devnull);
  rtu::TextWriter text(devnull);
  CheckingSink sink(json, text);
  rtu::DecodePipeline pipeline(options, sink);

  // Layout: [mode] then repeated [len (low 5 bits) | step] [len bytes...]
  std::size_t pos = 1;
  std::size_t payload = 0;
  rtu::Nanos t = 0;
  std::vector<std::uint8_t> chunk;
  while (pos < size) {
    const std::uint8_t control = data[pos++];
    const std::size_t len = (control & 0x1FU) + 1U;
    t += static_cast<rtu::Nanos>(control >> 5U) * 3 * rtu::kNanosPerMilli +
         static_cast<rtu::Nanos>(len) * options.line.char_time();
    chunk.assign(data + pos, data + std::min(size, pos + len));
    pos += chunk.size();
    if (chunk.empty()) break;
    payload += chunk.size();
    rtu::Chunk c;
    c.t_end = t;
    c.bytes = chunk;
    pipeline.push(c);
  }
  pipeline.finish();
  if (sink.bytes != payload) std::abort();
  return 0;
}
