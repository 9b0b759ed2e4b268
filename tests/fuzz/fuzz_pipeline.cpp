// Fuzz target for the whole decode path: chunks → framer(s) → tracker → device stage (slaves
// 1-4 named by the bundled maps, values collected) → JSONL and text.
// The input is split into chunks with fuzzer-chosen sizes and time steps, so the framer
// sees every mix of batched and per-byte timing, and optionally two receiving ports.
// Oracles: every input byte leaves in exactly one record, no record exceeds 256 bytes,
// records of one port leave in time order, and a run with a live capture's idle calls
// between the reads gives exactly the records of the replay without them (live ≡ replay),
// device issues included; every value the device stage collects has a name. The same bytes
// read one at a time give the same records read by read as in runs of one-byte reads. A first
// look at the first frames (identification's sample) leaves the records as they are.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <vector>

#include "dissect/device_stage.hpp"
#include "dissect/map_library.hpp"
#include "framing/framer.hpp"
#include "pairing/transaction_tracker.hpp"
#include "pipeline/decode_pipeline.hpp"
#include "pipeline/first_look_gate.hpp"
#include "report/jsonl_writer.hpp"
#include "report/text_writer.hpp"

namespace {

// What a record shows the user, for comparing two runs.
struct Seen {
  rtu::RecordKind kind;
  std::vector<std::uint8_t> bytes;
  rtu::Nanos t_start;
  rtu::Nanos gap;
  std::uint64_t issues;
  rtu::Role role;
  std::int64_t txn;
  rtu::Nanos latency;
  bool operator==(const Seen&) const = default;
};

class CheckingSink : public rtu::RecordSink {
 public:
  CheckingSink(rtu::RecordSink& json, rtu::RecordSink& text, bool one_port)
      : json_(json), text_(text), one_port_(one_port) {}
  void on_record(rtu::Record& record) override {
    if (record.size == 0 || record.size > rtu::kMaxAdu) std::abort();
    if (record.t_end < record.t_start) std::abort();
    if (one_port_ && last_start_ != rtu::kUnknownTime && record.t_start < last_start_) {
      std::abort();
    }
    last_start_ = record.t_start;
    if (record.device != nullptr) {
      for (const auto& v : record.device->values) {
        if (v.point.empty() || v.slave != record.slave()) std::abort();
      }
    }
    bytes += record.size;
    seen.push_back(Seen{record.kind,
                        {record.bytes().begin(), record.bytes().end()},
                        record.t_start,
                        record.gap_before,
                        record.issues.bits(),
                        record.role,
                        record.txn,
                        record.latency});
    json_.on_record(record);
    text_.on_record(record);
  }
  std::size_t bytes = 0;
  std::vector<Seen> seen;

 private:
  rtu::RecordSink& json_;
  rtu::RecordSink& text_;
  bool one_port_;
  rtu::Nanos last_start_ = rtu::kUnknownTime;
};

// A first look that wants `frames` frames and only counts them: what the gate holds while it
// lasts must reach the sink as it would have without it.
class FrameCountingLook final : public rtu::FirstLook, public rtu::PairingInput {
 public:
  explicit FrameCountingLook(std::uint64_t frames) : wanted_(frames) {}
  rtu::PairingInput& start_look(const rtu::CaptureInfo& /*info*/) override { return *this; }
  [[nodiscard]] bool seen_enough() const override { return seen_ >= wanted_; }
  void conclude(rtu::SampleEnd /*why*/) override {}
  void on_record(rtu::Record& record) override {
    if (record.kind == rtu::RecordKind::kFrame) ++seen_;
  }
  void advance(rtu::Nanos /*now*/) override {}
  void on_break() override {}

 private:
  std::uint64_t wanted_;
  std::uint64_t seen_ = 0;
};

struct Read {
  rtu::Nanos t_end;
  std::uint8_t port;
  std::vector<std::uint8_t> bytes;
};

// Decodes the reads; with `idle_step` > 0 also calls idle() every idle_step while no read
// is due, as a live capture's timer does. A live capture is idle only while no bytes wait
// in a driver, so a read's bytes were on the wire at most an adapter's delivery delay
// (the resolution, at least kDeliveryPatience) and a character before an idle moment:
// idle moments here keep to that, as they do on a real line.
// With `run` > 0 (and no idle moments), one-byte reads in a row on one port are handed over
// in runs of up to `run` reads, as a reading thread hands them over
// (DecodePipeline::push_byte_reads). With `look_frames` > 0, a first look at that many frames
// stands between the framing and the pairing (FirstLookGate).
std::vector<Seen> decode(const std::vector<Read>& reads, const rtu::PipelineOptions& options,
                         bool one_port, rtu::Nanos idle_step, std::size_t payload,
                         std::size_t run = 0, std::uint64_t look_frames = 0) {
  static rtu::OutputStream devnull("/dev/null");
  rtu::JsonlWriter json(devnull);
  rtu::TextWriter text(devnull);
  CheckingSink sink(json, text, one_port);
  static const rtu::dissect::MapLibrary maps = [] {
    rtu::dissect::MapLibrary library;
    if (!library.load_dir(RTUSCOPE_DISSECTORS_DIR).empty()) std::abort();
    return library;
  }();
  // What is learned (PT, CT) starts afresh with each run, as in a new process.
  rtu::dissect::DeviceTable devices;
  for (std::uint8_t slave = 1; slave <= maps.maps().size() && slave <= 4; ++slave) {
    devices.assign(slave, *maps.maps()[slave - 1], rtu::dissect::ModelOrigin::kConfigured);
  }
  rtu::dissect::DeviceStage stage(devices, sink, true);
  rtu::TransactionTracker tracker(rtu::TrackerConfig{options.response_timeout}, stage);
  FrameCountingLook look(look_frames);
  rtu::FirstLookGate gate(&look, tracker);
  std::optional<rtu::DecodePipeline> framing_and_pairing;
  if (look_frames > 0) {
    framing_and_pairing.emplace(options, static_cast<rtu::PairingInput&>(gate));
  } else {
    framing_and_pairing.emplace(options, stage);
  }
  rtu::DecodePipeline& pipeline = *framing_and_pairing;
  rtu::Nanos now = 0;
  const rtu::Nanos char_time = options.line.char_time();
  const rtu::Nanos delivery =
      std::max(options.timing_resolution, rtu::kDeliveryPatience) + char_time;
  std::vector<std::uint8_t> run_bytes;
  std::vector<rtu::Nanos> run_t_ends;
  std::uint8_t run_port = 0;
  const auto push_run = [&] {
    if (run_bytes.empty()) return;
    pipeline.push_byte_reads(rtu::ByteReads{run_bytes, run_t_ends.data(), 0, run_port});
    run_bytes.clear();
    run_t_ends.clear();
  };
  for (const auto& read : reads) {
    if (run > 0) {
      if (read.bytes.size() == 1 && (run_bytes.empty() || read.port == run_port)) {
        run_port = read.port;
        run_bytes.push_back(read.bytes[0]);
        run_t_ends.push_back(read.t_end);
        if (run_bytes.size() == run) push_run();
        continue;
      }
      push_run();
      if (read.bytes.size() == 1) {
        run_port = read.port;
        run_bytes.push_back(read.bytes[0]);
        run_t_ends.push_back(read.t_end);
        continue;
      }
    }
    const rtu::Nanos on_wire_from =
        read.t_end - static_cast<rtu::Nanos>(read.bytes.size()) * char_time;
    for (; idle_step > 0 && now + idle_step < read.t_end &&
           now + idle_step <= on_wire_from + delivery;
         now += idle_step) {
      pipeline.idle(now + idle_step);
    }
    rtu::Chunk c;
    c.t_end = read.t_end;
    c.bytes = read.bytes;
    c.port = read.port;
    pipeline.push(c);
    now = read.t_end;
  }
  push_run();
  pipeline.finish();
  if (sink.bytes != payload) std::abort();
  return std::move(sink.seen);
}

// Says where two runs part, so that a finding can be read without a debugger.
void report_first_difference(const std::vector<Seen>& replayed, const std::vector<Seen>& lived) {
  const auto show = [](const char* which, std::size_t i, const Seen& s) {
    std::fprintf(stderr,
                 "%s #%zu: kind %d, %zu bytes, t_start %lld, gap %lld, issues %llx, txn %lld\n",
                 which, i, static_cast<int>(s.kind), s.bytes.size(),
                 static_cast<long long>(s.t_start), static_cast<long long>(s.gap),
                 static_cast<unsigned long long>(s.issues), static_cast<long long>(s.txn));
  };
  std::size_t i = 0;
  while (i < replayed.size() && i < lived.size() && replayed[i] == lived[i]) ++i;
  std::fprintf(stderr, "live and replay part at record %zu of %zu / %zu\n", i, replayed.size(),
               lived.size());
  for (std::size_t k = i > 2 ? i - 2 : 0; k < i + 2; ++k) {
    if (k < replayed.size()) show("replay", k, replayed[k]);
    if (k < lived.size()) show("live  ", k, lived[k]);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  rtu::PipelineOptions options;
  options.line.baud = (data[0] & 1U) != 0 ? 9600 : 115200;
  options.timing_resolution = (data[0] & 2U) != 0 ? 16 * rtu::kNanosPerMilli : rtu::kNanosPerMicro;
  options.response_timeout = 100 * rtu::kNanosPerMilli;
  const bool two_ports = (data[0] & 4U) != 0;
  const rtu::Nanos idle_step = (1 + ((data[0] >> 3U) & 7U)) * rtu::kNanosPerMilli / 2;

  // Layout: [mode] then repeated [len (low 5 bits) | step] [len bytes...]
  std::size_t pos = 1;
  std::size_t payload = 0;
  rtu::Nanos t = 0;
  std::vector<Read> reads;
  while (pos < size) {
    const std::uint8_t control = data[pos++];
    const std::size_t len = (control & 0x1FU) + 1U;
    t += static_cast<rtu::Nanos>(control >> 5U) * 3 * rtu::kNanosPerMilli +
         static_cast<rtu::Nanos>(len) * options.line.char_time();
    if (pos >= size) break;
    Read read{t, 0, {data + pos, data + std::min(size, pos + len)}};
    pos += read.bytes.size();
    if (two_ports) read.port = read.bytes[0] & 1U;
    payload += read.bytes.size();
    reads.push_back(std::move(read));
  }
  const auto replayed = decode(reads, options, !two_ports, 0, payload);
  const auto lived = decode(reads, options, !two_ports, idle_step, payload);
  if (lived != replayed) {
    report_first_difference(replayed, lived);
    std::abort();
  }
  const std::uint64_t look_frames = 1 + data[size - 1] % 16U;
  const auto looked_first = decode(reads, options, !two_ports, 0, payload, 0, look_frames);
  if (looked_first != replayed) {
    report_first_difference(replayed, looked_first);
    std::abort();
  }
  // The same bytes read one at a time (as a per-byte source reads them, each a character
  // after the one before): read by read, and in runs of one-byte reads, the same records.
  std::vector<Read> one_byte_reads;
  for (const Read& read : reads) {
    for (std::size_t i = 0; i < read.bytes.size(); ++i) {
      const auto later = static_cast<rtu::Nanos>(read.bytes.size() - 1 - i);
      one_byte_reads.push_back(
          Read{read.t_end - later * options.line.char_time(), read.port, {read.bytes[i]}});
    }
  }
  const auto read_by_read = decode(one_byte_reads, options, !two_ports, 0, payload);
  const std::size_t run = 1 + (data[0] >> 6U) * 21U;  // 1, 22, 43 or 64 reads
  const auto in_runs = decode(one_byte_reads, options, !two_ports, 0, payload, run);
  if (in_runs != read_by_read) {
    report_first_difference(read_by_read, in_runs);
    std::abort();
  }
  return 0;
}
