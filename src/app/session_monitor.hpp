#pragma once
// The event log and health summaries of a live session (`--events`, `--summary-every`).
// Records give timeouts, exceptions and line errors as they pass; the capture and the
// recorder tell about ports lost and back and new files; a timer looks for new findings
// every 10 s and writes a summary every period (into the events, and into the recording as
// a comment). All of it runs on the session's event loop, after records are produced.
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <memory>
#include <optional>
#include <string>

#include "core/output_stream.hpp"
#include "pipeline/live_capture.hpp"
#include "pipeline/pcapng_recorder.hpp"
#include "report/event_log.hpp"
#include "report/traffic_stats.hpp"

namespace rtu::app {

class SessionMonitor {
 public:
  static constexpr Nanos kFindingsPeriod = 10 * kNanosPerSecond;

  // `events_path` "" = no event log; `summary_every` 0 = no summaries. `stats` and `devices`
  // (not owned) are the report's. Opens the event log now: throws InputError for a bad path.
  SessionMonitor(boost::asio::io_context& io, const std::string& events_path, Nanos summary_every,
                 std::string bus, const TrafficStats& stats, const dissect::DeviceTable& devices);

  // The sink for the run's records (after the device stage), or null without an event log.
  [[nodiscard]] RecordSink* sink() { return record_events_ ? &*record_events_ : nullptr; }

  // The capture started: listens to it and to `recorder` (may be null), starts the timers.
  void start(LiveCapture& capture, PcapngRecorder* recorder);
  // The capture stopped (records flushed): last findings, and the stop event.
  void stop();
  // SIGHUP: the event log goes on in a file opened again at its path. Throws InputError when
  // it cannot be opened (the log goes on in the file already open).
  void reopen_events();

 private:
  void arm_findings();
  void arm_summary();

  boost::asio::steady_timer findings_timer_;
  boost::asio::steady_timer summary_timer_;
  Nanos summary_every_;
  const TrafficStats& stats_;
  std::optional<OutputStream> out_;
  std::optional<EventLog> log_;
  std::optional<RecordEvents> record_events_;
  std::optional<FindingEvents> findings_;
  HealthSummary summary_{nullptr};
  LiveCapture* capture_ = nullptr;
  PcapngRecorder* recorder_ = nullptr;
};

}  // namespace rtu::app
