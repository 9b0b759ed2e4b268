#include "pipeline/decode_pipeline.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include "core/crc16.hpp"
#include "framing/frame_classifier.hpp"
#include "framing/framer.hpp"
#include "pairing/transaction_tracker.hpp"
#include "pipeline/port_merge.hpp"

namespace rtu {

namespace {

// More receivers than this in one capture are taken as the last one.
constexpr std::size_t kMaxPorts = 8;

}  // namespace

struct DecodePipeline::Impl {
  Impl(const PipelineOptions& opts, RecordSink& out)
      : own_tracker(std::in_place, TrackerConfig{opts.response_timeout}, out),
        pairing(*own_tracker),
        merge(pairing, framers),
        options(opts) {
    add_port();
  }
  Impl(const PipelineOptions& opts, PairingInput& next)
      : pairing(next), merge(pairing, framers), options(opts) {
    add_port();
  }

  // One framer per receiving port, created when its first chunk comes.
  Framer& framer_for(std::size_t port) {
    port = std::min(port, kMaxPorts - 1);
    while (framers.size() <= port) add_port();
    return *framers[port];
  }
  [[nodiscard]] FramerConfig framer_config() const {
    return FramerConfig{options.line, std::max<Nanos>(options.timing_resolution, 0),
                        options.per_byte_timing, options.learn_resolution};
  }
  // How far the line is decided at `now`, when nothing was read before it (see idle()).
  [[nodiscard]] Nanos decided_until(Nanos now) const {
    Nanos decided = now;
    for (const auto& framer : framers) {
      decided = std::min(decided, framer->earliest_unread_start(now));
    }
    const Nanos oldest = merge.oldest_pending_start();
    return oldest != kUnknownTime ? std::min(decided, oldest) : decided;
  }
  void add_port() {
    outputs.push_back(std::make_unique<PortOutput>(merge, framers.size()));
    framers.push_back(std::make_unique<Framer>(framer_config(), *outputs.back()));
    merge.set_port_count(framers.size());
  }

  std::optional<TransactionTracker> own_tracker;  // absent when pairing is handed on
  PairingInput& pairing;
  // One framer per port, each writing to the merge through its output; the merge asks
  // them what they still hold.
  std::vector<std::unique_ptr<PortOutput>> outputs;
  std::vector<std::unique_ptr<Framer>> framers;
  PortMerge merge;
  PipelineOptions options;
  bool started = false;
  Record imported;
  Record& imported_record(RecordKind kind, std::span<const std::uint8_t> bytes, Nanos t_start,
                          Nanos t_end, std::uint64_t origin);
  Nanos last_import_end = kUnknownTime;
  std::uint64_t import_seq = 0;

  void flag_t35(Record& rec) const;
  void push_noise_records(std::span<const std::uint8_t> bytes, Nanos t_start, Nanos t_end,
                          std::uint64_t origin);
  void push_oversize_frame(std::span<const std::uint8_t> bytes, Nanos t_start, Nanos t_end,
                           std::uint64_t origin);
  void push_too_long_frame(std::span<const std::uint8_t> bytes, Nanos t_start, Nanos t_end,
                           std::uint64_t origin);

  // Passes what a framer finds inside one imported record on as imported records: numbered
  // in the import sequence, the first one's gap measured from the previous import (the
  // framer saw nothing before it).
  struct SplitRelay final : RecordSink {
    explicit SplitRelay(Impl& pipeline) : impl(pipeline) {}
    void on_record(Record& rec) override;
    Impl& impl;
    bool first = true;
  };
};

DecodePipeline::DecodePipeline(const PipelineOptions& options, RecordSink& sink)
    : impl_(std::make_unique<Impl>(options, sink)) {}

DecodePipeline::DecodePipeline(const PipelineOptions& options, PairingInput& pairing)
    : impl_(std::make_unique<Impl>(options, pairing)) {}

DecodePipeline::~DecodePipeline() = default;

void DecodePipeline::start(const CaptureInfo& info) {
  if (impl_->started) return;
  impl_->started = true;
  impl_->pairing.on_capture(info);
}

void DecodePipeline::start_as_configured() {
  CaptureInfo info;
  info.line = impl_->options.line;
  info.timing_resolution = impl_->options.timing_resolution;
  info.per_byte_timing = impl_->options.per_byte_timing;
  info.response_timeout = impl_->options.response_timeout;
  start(info);
}

void DecodePipeline::push(const Chunk& chunk) {
  if (!impl_->started) start_as_configured();
  if (chunk.bytes.empty()) return;
  push_read(impl_->framer_for(chunk.port), chunk);
}

void DecodePipeline::push_byte_reads(const ByteReads& reads) {
  if (!impl_->started) start_as_configured();
  if (reads.size() == 0) return;
  Framer& framer = impl_->framer_for(reads.port);
  if (impl_->framers.size() > 1) {
    for (std::size_t i = 0; i < reads.size(); ++i) push_read(framer, reads.read(i));
    return;
  }
  // One port: most reads of a run only add a byte to a frame whose head waits for more
  // (Framer::push_if_head_waits). Such a read emits no record, so the idle() before it
  // only moves the decided time on, and a later move, with no record between, covers it
  // (a request times out once the decided time passes its deadline). So that move is made
  // once, for the last such read, before the next read that may emit (whose own idle()
  // then comes after it, as it would have) or at the run's end.
  // The latest time such a read brought is kept (times that go backwards move nothing).
  bool waited = false;
  Nanos latest_waited = 0;
  const auto catch_up = [&] {
    if (waited) impl_->pairing.advance(impl_->decided_until(latest_waited));
    waited = false;
  };
  for (std::size_t i = 0; i < reads.size(); ++i) {
    Nanos latest = 0;
    const std::size_t taken = framer.push_reads_while_head_waits(reads, i, latest);
    if (taken > 0) {
      latest_waited = waited ? std::max(latest_waited, latest) : latest;
      waited = true;
      i += taken;
      if (i == reads.size()) break;
    }
    // A read the shortcut declined.
    catch_up();
    // push_read() without the merge, which holds nothing with one port.
    idle(reads.t_ends[i]);
    framer.push_without_shortcut(reads.read(i));
  }
  catch_up();
}

void DecodePipeline::push_read(Framer& framer, const Chunk& chunk) {
  // Nothing was read, on any port, before this read completed: the line was quiet up to
  // the moment its framer knows of (Framer::quiet_known_until), and no later.
  if (const Nanos quiet = framer.quiet_known_until(chunk); quiet != kUnknownTime) idle(quiet);
  framer.push(chunk);
  impl_->merge.drain();
}

Nanos DecodePipeline::timing_resolution() const {
  Nanos res = 0;
  for (const auto& framer : impl_->framers) res = std::max(res, framer->resolution());
  return res;
}

// Fills the record for bytes whose boundaries the input already gave (imported files):
// at most one record's worth, timed as given, its gap measured from the previous one.
Record& DecodePipeline::Impl::imported_record(RecordKind kind, std::span<const std::uint8_t> bytes,
                                              Nanos t_start, Nanos t_end, std::uint64_t origin) {
  Record& rec = imported;
  rec.reset_keeping_storage();
  rec.kind = kind;
  rec.size = static_cast<std::uint16_t>(std::min(bytes.size(), kMaxAdu));
  std::memcpy(rec.storage.data(), bytes.data(), rec.size);
  rec.t_start = t_start;
  rec.t_end = t_end;
  rec.origin = origin;
  rec.seq = import_seq++;
  if (last_import_end != kUnknownTime) {
    rec.gap_before = std::max<Nanos>(0, t_start - last_import_end);
  }
  last_import_end = t_end;
  return rec;
}

void DecodePipeline::Impl::flag_t35(Record& rec) const {
  if (rec.gap_before != kUnknownTime &&
      rec.gap_before + options.timing_resolution < options.line.t3_5()) {
    rec.issues.add(IssueId::kT35);
  }
}

void DecodePipeline::push_frame(std::span<const std::uint8_t> adu, Nanos t_start, Nanos t_end,
                                std::uint64_t origin) {
  if (!impl_->started) start(CaptureInfo{});
  if (adu.size() > kMaxAdu) {
    impl_->push_oversize_frame(adu, t_start, t_end, origin);
    return;
  }
  Record& rec = impl_->imported_record(RecordKind::kFrame, adu, t_start, t_end, origin);
  impl_->flag_t35(rec);
  classify_frame(rec);
  impl_->pairing.on_record(rec);
}

// A frame record longer than RTU allows cannot be kept as one record, and is rarely one
// frame: other tools glue frames that came close together, or keep bytes that form none.
// Unless its CRC holds over all of it (then it is one frame: push_too_long_frame), its
// bytes go through a framer of their own, as one chunk ending at `t_end`, so glued frames
// come out as frames and the rest as noise; every byte lands in exactly one record. The
// timestamps show no silence inside the record, so the records after its first have no
// known gap.
void DecodePipeline::Impl::push_oversize_frame(std::span<const std::uint8_t> bytes, Nanos t_start,
                                               Nanos t_end, std::uint64_t origin) {
  if (crc16_valid(bytes)) {
    push_too_long_frame(bytes, t_start, t_end, origin);
    return;
  }
  SplitRelay relay(*this);
  // A framer holds a window of a few kB: made only for the rare oversize record.
  FramerConfig config = framer_config();
  config.per_byte_exact = false;  // one record's bytes: only its end time is known
  auto framer_of_record = std::make_unique<Framer>(config, relay);
  Chunk chunk;
  chunk.t_end = t_end;
  chunk.bytes = bytes;
  chunk.origin = origin;
  framer_of_record->push(chunk);
  framer_of_record->finish();
}

void DecodePipeline::Impl::SplitRelay::on_record(Record& rec) {
  rec.seq = impl.import_seq++;
  if (first) {
    first = false;
    if (impl.last_import_end != kUnknownTime) {
      rec.gap_before = std::max<Nanos>(0, rec.t_start - impl.last_import_end);
    }
    if (rec.kind == RecordKind::kFrame) impl.flag_t35(rec);
  }
  impl.last_import_end = rec.t_end;
  impl.pairing.on_record(rec);
}

// The CRC holds over all the bytes: one frame, only longer than the 256 bytes RTU allows
// (a device or gateway breaking the limit). What a user should see is that frame, flagged
// too_long, not noise and not a CRC error. A record holds 256 bytes, so the frame record
// keeps the first 256 and the rest follows as noise. crc_ok stays false: the record does
// not hold the CRC, and nothing may decode its cut PDU as if it were whole.
void DecodePipeline::Impl::push_too_long_frame(std::span<const std::uint8_t> bytes, Nanos t_start,
                                               Nanos t_end, std::uint64_t origin) {
  const auto tail = bytes.subspan(kMaxAdu);
  const Nanos tail_time = static_cast<Nanos>(tail.size()) * options.line.char_time();
  const Nanos split = std::clamp(t_end - tail_time, t_start, t_end);
  Record& rec = imported_record(RecordKind::kFrame, bytes.first(kMaxAdu), t_start, split, origin);
  flag_t35(rec);
  classify_frame(rec);
  rec.issues.remove(IssueId::kCrc);
  rec.issues.add(IssueId::kTooLong);
  pairing.on_record(rec);
  push_noise_records(tail, split, t_end, origin);
}

void DecodePipeline::push_noise(std::span<const std::uint8_t> bytes, Nanos t_start, Nanos t_end,
                                std::uint64_t origin) {
  if (!impl_->started) start(CaptureInfo{});
  impl_->push_noise_records(bytes, t_start, t_end, origin);
}

void DecodePipeline::Impl::push_noise_records(std::span<const std::uint8_t> bytes, Nanos t_start,
                                              Nanos t_end, std::uint64_t origin) {
  // Longer spans than a record holds become several records, so no byte is lost.
  while (!bytes.empty()) {
    Record& rec = imported_record(RecordKind::kNoise, bytes, t_start, t_end, origin);
    rec.issues.add(IssueId::kNoiseBytes);
    pairing.on_record(rec);
    bytes = bytes.subspan(rec.size);
  }
}

void DecodePipeline::idle(Nanos now) {
  if (!impl_->started) return;
  // A request's fate is decided only up to where a record still to come could start: one
  // a framer or the merge still holds, or one made of bytes an adapter still holds (read
  // later, but stamped back to when they were on the wire). Deciding later than that is
  // what makes the verdict the same as the replay's, which sees no idle moments.
  for (auto& framer : impl_->framers) framer->advance(now);
  impl_->pairing.advance(impl_->decided_until(now));
}

bool DecodePipeline::awaits_idle() const {
  if (!impl_->started) return false;
  // Pairing handed on: whether a request still waits is not known here.
  if (!impl_->own_tracker) return true;
  for (const auto& framer : impl_->framers) {
    if (framer->oldest_pending_start() != kUnknownTime) return true;
  }
  return impl_->merge.oldest_pending_start() != kUnknownTime ||
         impl_->own_tracker->awaits_timeout();
}

Nanos DecodePipeline::next_idle_decision() const {
  Nanos next = kUnknownTime;
  const auto take = [&next](Nanos t) {
    if (t != kUnknownTime && (next == kUnknownTime || t < next)) next = t;
  };
  Nanos reach = 0;
  for (const auto& framer : impl_->framers) {
    take(framer->decidable_at());
    reach = std::max(reach, framer->unread_reach());
  }
  // Pairing handed on: when a waiting request times out is not known here.
  if (!impl_->own_tracker) return kUnknownTime;
  // idle() decides timeouts only up to where unread bytes could start (see idle()).
  const Nanos timeout = impl_->own_tracker->timeout_at();
  if (timeout != kUnknownTime) take(timeout + reach);
  return next;
}

void DecodePipeline::finish() {
  for (auto& framer : impl_->framers) framer->finish();
  impl_->merge.flush();
  impl_->pairing.on_finish();
}

void DecodePipeline::break_capture() {
  for (auto& framer : impl_->framers) framer->break_capture();
  impl_->merge.flush();
  impl_->pairing.on_break();
}

}  // namespace rtu
