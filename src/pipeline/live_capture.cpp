#include "pipeline/live_capture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <boost/asio/post.hpp>
#include <chrono>

namespace rtu {

namespace asio = boost::asio;

// Counts what passes to the output, for the summary.
class LiveCapture::Counter final : public RecordSink {
 public:
  Counter(RecordSink& out, LiveSummary& summary) : out_(out), summary_(summary) {}
  void on_capture(const CaptureInfo& info) override { out_.on_capture(info); }
  void on_record(Record& record) override {
    if (record.kind == RecordKind::kNoise) {
      ++summary_.noise_records;
    } else {
      ++summary_.frames;
      if (!record.crc_ok) ++summary_.crc_errors;
      if (record.role == Role::kResponse && record.txn >= 0) ++summary_.transactions;
      if (record.issues.has(IssueId::kTimeout) && record.role == Role::kRequest) {
        ++summary_.timeouts;
      }
      if (!record.issues.empty()) ++summary_.frames_with_issues;
    }
    out_.on_record(record);
  }
  void on_finish() override { out_.on_finish(); }

 private:
  RecordSink& out_;
  LiveSummary& summary_;
};

struct LiveCapture::Port {
  Port(asio::io_context& io, CaptureClock& clock, SerialConfig config, std::size_t port_index)
      : source(io, clock, std::move(config)), reopen_timer(io), index(port_index) {}
  SerialSource source;
  asio::steady_timer reopen_timer;
  std::size_t index;
  Nanos lost_at = kUnknownTime;
  bool lost_bytes = false;  // the next byte follows a gap: flagged kOverrun
  std::vector<std::uint8_t> errors;
};

namespace {

std::chrono::nanoseconds as_duration(Nanos n) {
  return std::chrono::nanoseconds(n);
}

}  // namespace

LiveCapture::LiveCapture(asio::io_context& io, Clock& clock, LiveOptions options, RecordSink& sink,
                         ChunkRecorder* recorder, Notify notify)
    : io_(io),
      clock_(clock),
      options_(std::move(options)),
      recorder_(recorder),
      notify_(std::move(notify)),
      counter_(std::make_unique<Counter>(sink, summary_)),
      idle_timer_(io),
      flush_timer_(io),
      stop_timer_(io) {
  for (std::size_t i = 0; i < options_.ports.size(); ++i) {
    SerialConfig config;
    config.path = options_.ports[i];
    config.line = options_.line;
    ports_.push_back(std::make_unique<Port>(io_, clock_, std::move(config), i));
  }
}

LiveCapture::~LiveCapture() = default;

void LiveCapture::start() {
  // Open everything first, so a wrong second port fails before anything is printed.
  Nanos resolution = 0;
  for (auto& port : ports_) {
    const SerialStatus& status = port->source.open();
    for (const auto& note : status.notes) notify_(note);
    resolution = std::max(resolution, status.resolution);
  }
  info_.line = options_.line;
  info_.timing_resolution = resolution;
  summary_.declared_resolution = resolution;
  info_.per_byte_timing = false;
  info_.response_timeout = options_.response_timeout;
  info_.warnings = options_.warnings;
  for (std::size_t i = 0; i < ports_.size(); ++i) {
    info_.source += (i == 0 ? "" : " + ") + options_.ports[i];
  }
  PipelineOptions pipeline_options;
  pipeline_options.line = options_.line;
  pipeline_options.response_timeout = options_.response_timeout;
  pipeline_options.timing_resolution = resolution;
  pipeline_ = std::make_unique<DecodePipeline>(pipeline_options, *counter_);
  pipeline_->start(info_);
  if (recorder_ != nullptr) {
    for (auto& port : ports_) {
      recorder_->add_port(port->index, port->source.config().path, options_.line,
                          port->source.status(), options_.response_timeout);
    }
    recorder_->flush();
  }
  started_at_ = clock_.now();
  for (auto& port : ports_) start_port(*port);
  arm_idle_for_pipeline();
  if (recorder_ != nullptr) schedule_flush();
  if (options_.duration > 0) {
    stop_timer_.expires_after(as_duration(options_.duration));
    stop_timer_.async_wait([this](const boost::system::error_code& ec) {
      if (!ec) stop();
    });
  }
}

void LiveCapture::start_port(Port& port) {
  port.source.start([this, &port](const Chunk& chunk) { on_chunk(port, chunk); },
                    [this, &port](const std::error_code& ec) { on_port_error(port, ec); });
}

void LiveCapture::on_chunk(Port& port, const Chunk& read) {
  if (stopped_) return;
  Chunk chunk = read;
  chunk.port = static_cast<std::uint8_t>(port.index);
  if (port.lost_bytes && !chunk.bytes.empty()) {
    // Bytes were lost while the port was away: the first byte after the gap says so, in
    // the decode as in the recording (importers flag the byte after a data-lost event).
    port.errors.assign(chunk.bytes.size(), kLineOk);
    if (!read.errors.empty()) port.errors.assign(read.errors.begin(), read.errors.end());
    port.errors.front() |= kOverrun;
    chunk.errors = port.errors;
    port.lost_bytes = false;
  }
  ++summary_.chunks;
  summary_.bytes += chunk.bytes.size();
  if (chunk.read_late) ++summary_.late_reads;
  if (!chunk.bytes.empty()) summary_.last_byte_at = chunk.t_end;
  for (const auto e : chunk.errors) {
    if (e != kLineOk) ++summary_.line_error_bytes;
  }
  if (recorder_ != nullptr) recorder_->on_chunk(port.index, chunk);
  pipeline_->push(chunk);
  // Armed already for a moment no later than what this read left to decide: nothing to do
  // (most reads), else the timer moves.
  if (!idle_armed_) {
    arm_idle_for_pipeline();
  } else if (const Nanos due = pipeline_->next_idle_decision();
             due != kUnknownTime && due + options_.idle_slack < idle_due_) {
    arm_idle_for_pipeline();
  }
}

void LiveCapture::on_port_error(Port& port, const std::error_code& error) {
  if (stopped_) return;
  ++summary_.disconnects;
  port.lost_at = clock_.now();
  port.lost_bytes = true;
  const std::string reason = fmt::format("{}: {}", port.source.config().path, error.message());
  notify_(fmt::format("{}; reopening it when it comes back", reason));
  if (port_listener_) {
    port_listener_(PortEvent{false, port.source.config().path, error.message(), port.lost_at});
  }
  if (recorder_ != nullptr) {
    recorder_->on_gap(port.index, port.lost_at, reason);
    recorder_->flush();
  }
  schedule_reopen(port);
}

void LiveCapture::schedule_reopen(Port& port) {
  port.reopen_timer.expires_after(as_duration(options_.reopen_period));
  port.reopen_timer.async_wait([this, &port](const boost::system::error_code& ec) {
    if (ec || stopped_) return;
    try {
      port.source.open();
    } catch (const SerialOpenError&) {
      schedule_reopen(port);
      return;
    }
    const Nanos back = clock_.now();
    ++summary_.reconnects;
    notify_(fmt::format("{}: back after {:.1f} s", port.source.config().path,
                        to_seconds(back - port.lost_at)));
    if (port_listener_) port_listener_(PortEvent{true, port.source.config().path, "", back});
    start_port(port);
  });
}

// The idle timer runs only while the pipeline has something an idle moment could decide,
// and wakes up idle_slack after that can first be decided: on a quiet line the capture
// sleeps until the next read, and a request waiting for its answer costs one wake-up, not one
// every idle_period. Waking up was most of what a live run cost on a quiet or lightly used
// bus; on a busy one, a wake-up at the end of every frame was, where the next frame's first
// read a moment later would have decided the same (the slack lets it).
void LiveCapture::arm_idle_for_pipeline() {
  if (!pipeline_->awaits_idle()) {
    idle_armed_ = false;  // the next read arms it again
    return;
  }
  const Nanos now = clock_.now();
  const Nanos due = pipeline_->next_idle_decision();
  // Unknown, or already past and still undecided: try again after the usual period.
  schedule_idle(due != kUnknownTime && due > now ? due - now + options_.idle_slack
                                                 : options_.idle_period);
}

void LiveCapture::schedule_idle(Nanos delay) {
  idle_armed_ = true;
  idle_due_ = clock_.now() + delay;
  idle_timer_.expires_after(as_duration(delay));
  idle_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || stopped_) return;
    ++summary_.idle_wakeups;
    // Reads since it was armed left nothing that can be decided yet: wait for what they left.
    if (const Nanos due = pipeline_->next_idle_decision();
        due != kUnknownTime && due > clock_.now()) {
      arm_idle_for_pipeline();
      return;
    }
    // The line is quiet only if no bytes wait in a driver, and no read that completed
    // meanwhile waits to be handled: the check is posted behind such handlers, with the
    // time taken now, so a late read is pushed (and seen as newer) before it.
    bool waiting = false;
    for (auto& port : ports_) waiting = waiting || port->source.pending_input() > 0;
    if (waiting) {
      schedule_idle(options_.idle_period);
      return;
    }
    const Nanos now = clock_.now();
    asio::post(io_, [this, now] {
      if (stopped_) return;
      // The moment decided at is one with no input pending, and the reads taken before it
      // have been handled now: a read that comes late after it carries it, and a replay
      // decides there as this does.
      for (auto& port : ports_) port->source.note_quiet_until(now);
      pipeline_->idle(now);
      arm_idle_for_pipeline();
      note_ports_free();
    });
  });
}

void LiveCapture::schedule_flush() {
  flush_timer_.expires_after(as_duration(options_.flush_period));
  flush_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || stopped_) return;
    recorder_->flush();
    schedule_flush();
    note_ports_free();
  });
}

// The work a timer's handler did is no delay of a read whose bytes come after it.
void LiveCapture::note_ports_free() {
  for (auto& port : ports_) port->source.note_free_moment();
}

void LiveCapture::stop() {
  if (stopped_) return;
  stopped_ = true;
  const Nanos now = clock_.now();
  for (auto& port : ports_) {
    port->reopen_timer.cancel();
    port->source.close();
  }
  idle_timer_.cancel();
  flush_timer_.cancel();
  stop_timer_.cancel();
  if (pipeline_) {
    pipeline_->idle(now);
    pipeline_->finish();
  }
  if (recorder_ != nullptr) {
    recorder_->on_end(now);
    recorder_->flush();
  }
  summary_.duration = started_at_ != 0 ? now - started_at_ : 0;
  summary_.timing_resolution = pipeline_ ? pipeline_->timing_resolution() : 0;
}

}  // namespace rtu
