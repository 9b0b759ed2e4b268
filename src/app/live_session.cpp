#include "app/live_session.hpp"

#include <fmt/format.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "app/metrics_endpoint.hpp"
#include "app/record_writer.hpp"
#include "app/reopen_on_hangup.hpp"
#include "app/run_report.hpp"
#include "app/session_monitor.hpp"
#include "core/input_error.hpp"
#include "core/output_error.hpp"
#include "core/output_stream.hpp"
#include "dissect/device_stage.hpp"
#include "pipeline/record_fanout.hpp"

namespace rtu::app {
namespace {

// Every 20 ms: calls `periodic`, asks `finished` and stops the capture once it says so.
class FinishWatch {
 public:
  FinishWatch(boost::asio::io_context& io, std::function<bool()> finished,
              std::function<void()> periodic, LiveCapture& capture)
      : timer_(io),
        finished_(std::move(finished)),
        periodic_(std::move(periodic)),
        capture_(capture) {
    if (finished_ || periodic_) arm();
  }

 private:
  void arm() {
    timer_.expires_after(std::chrono::milliseconds(20));
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (ec) return;
      if (periodic_) periodic_();
      if (finished_ && finished_()) {
        capture_.stop();
      } else {
        arm();
      }
    });
  }

  boost::asio::steady_timer timer_;
  std::function<bool()> finished_;
  std::function<void()> periodic_;
  LiveCapture& capture_;
};

// The bus's name in metrics: the one given, else the first port's file name ("ttyUSB0").
std::string bus_name_for(const LiveSessionSetup& setup) {
  if (!setup.bus_name.empty()) return setup.bus_name;
  if (setup.capture.ports.empty()) return "bus";
  return std::filesystem::path(setup.capture.ports.front()).filename().string();
}

}  // namespace

void run_live_session(const LiveSessionSetup& setup, DeviceSetup& devices,
                      const LiveSessionHooks& hooks) {
  // Records reach the output whole, once the handler that made them (a read, an idle
  // moment) is done: one write per read rather than one per record (see the loop below).
  OutputStream out(setup.output);
  out.keep_records_whole();
  const auto writer =
      setup.frames_sink != nullptr ? nullptr : make_record_writer(setup.format, out);
  std::unique_ptr<PcapngRecorder> recorder;
  if (!setup.record_path.empty()) {
    recorder = std::make_unique<PcapngRecorder>(setup.record_path, setup.rotation);
    recorder->set_bus_name(bus_name_for(setup));
  }
  ChunkRecorder* const chunk_recorder =
      setup.chunk_recorder != nullptr ? setup.chunk_recorder : recorder.get();

  // Frames go to the screen (or a file) and, when reported on, to the report's statistics.
  RecordFanout sinks;
  sinks.add(writer ? *writer : *setup.frames_sink);
  std::optional<RunReport> report;
  std::optional<OutputStream> report_out;  // opened now: a bad path fails before the run
  if (!setup.report_path.empty()) report_out.emplace(setup.report_path);
  // Metrics, events and summaries read the report's statistics: such a run gathers them too.
  const bool with_metrics = !setup.metrics_address.empty();
  const bool with_monitor = !setup.events_path.empty() || setup.summary_every > 0;
  if (report_out || setup.always_report || with_metrics || with_monitor) {
    report.emplace(devices);
    sinks.add(report->sink());
  }
  for (RecordSink* sink : setup.extra_sinks) sinks.add(*sink);
  const std::string bus_name = bus_name_for(setup);
  std::optional<BusMetrics> metrics;
  if (with_metrics) {
    metrics.emplace(bus_name, report->stats());
    sinks.add(*metrics);
  }
  boost::asio::io_context io;
  std::optional<SessionMonitor> monitor;
  if (with_monitor) {
    monitor.emplace(io, setup.events_path, setup.summary_every, bus_name, report->stats(),
                    devices.table);
    if (monitor->sink() != nullptr) sinks.add(*monitor->sink());
  }
  // One decode per frame: the screen and the report read the same device stage.
  dissect::DeviceStage stage(devices.table, sinks,
                             report.has_value() || !setup.extra_sinks.empty());

  SystemClock clock;
  const std::string& prefix = setup.prefix;
  LiveCapture capture(io, clock, setup.capture, stage, chunk_recorder,
                      [&prefix, &hooks](const std::string& m) {
                        if (hooks.on_note) {
                          hooks.on_note(m);
                        } else {
                          fmt::print(stderr, "{}: {}\n", prefix, m);
                        }
                      });
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int) {
    if (ec) return;
    if (hooks.on_signal) {
      hooks.on_signal();
    } else {
      capture.stop();
    }
  });
  // Output that cannot be written ends the run cleanly; the first such error is the one
  // the run exits with.
  std::optional<OutputError> output_error;
  bool stop_for_output = false;  // stopped from the loop, not from inside a read's handling
  if (recorder) {
    recorder->set_failure_listener([&](const std::string& message) {
      if (setup.stop_on_write_error) {
        fmt::print(stderr, "{}: recording stopped: {}; stopping (--stop-on-write-error)\n", prefix,
                   message);
        if (!output_error) output_error.emplace(message);
        stop_for_output = true;
      } else {
        fmt::print(stderr, "{}: recording stopped: {}; decoding goes on\n", prefix, message);
      }
    });
  }
  const ReopenOnHangup hangup(io, capture, recorder.get(), monitor ? &*monitor : nullptr, prefix);
  std::optional<MetricsEndpoint> endpoint;
  if (metrics) endpoint.emplace(io, setup.metrics_address, *metrics, capture, recorder.get());
  capture.start();
  if (monitor) monitor->start(capture, recorder.get());
  if (endpoint) fmt::print(stderr, "{}: serving metrics on {}\n", prefix, endpoint->url());
  if (hooks.on_listening) hooks.on_listening(capture);
  {
    const FinishWatch watch(io, hooks.finished, hooks.periodic, capture);
    while (!capture.stopped()) {
      try {
        io.run_one();
        out.flush();
      } catch (const OutputError& e) {
        // Said when the run ends, as the reason it exits with status 1.
        if (!output_error) output_error.emplace(e);
        stop_for_output = true;
      }
      if (stop_for_output && !capture.stopped()) capture.stop();
    }
  }
  signals.cancel();
  try {
    out.flush();
  } catch (const OutputError& e) {
    if (!output_error) output_error.emplace(e);
  }
  if (monitor) monitor->stop();
  if (hooks.on_stopped) hooks.on_stopped(capture.summary(), recorder.get());

  if (report) {
    report->finish(capture.summary().timing_resolution);
    if (report_out || setup.always_report) report->print_findings(stderr, 3);
    if (report_out) {
      report->write(*report_out, setup.report_format.empty() ? report_format_for(setup.report_path)
                                                             : setup.report_format);
      report_out->flush();
      fmt::print(stderr, "{}: report written to {}\n", prefix, setup.report_path);
    }
  }
  if (output_error) throw *output_error;
}

}  // namespace rtu::app
