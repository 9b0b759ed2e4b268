#include "app/session_monitor.hpp"

#include <chrono>
#include <utility>

namespace rtu::app {

SessionMonitor::SessionMonitor(boost::asio::io_context& io, const std::string& events_path,
                               Nanos summary_every, std::string bus, const TrafficStats& stats,
                               const dissect::DeviceTable& devices)
    : findings_timer_(io), summary_timer_(io), summary_every_(summary_every), stats_(stats) {
  if (!events_path.empty()) {
    // A restarted service appends to the log it finds, as log shippers expect.
    out_.emplace(events_path, OutputStream::Mode::kAppend);
    log_.emplace(*out_, std::move(bus));
    record_events_.emplace(*log_, &devices);
    findings_.emplace(*log_);
  }
  summary_ = HealthSummary(log_ ? &*log_ : nullptr);
}

void SessionMonitor::start(LiveCapture& capture, PcapngRecorder* recorder) {
  capture_ = &capture;
  recorder_ = recorder;
  if (log_) {
    log_->emit(EventKind::kStart, capture.now(),
               {{EventField::kPort, std::string_view(capture.info().source)}});
    capture.set_port_listener([this](const PortEvent& e) {
      if (e.back) {
        log_->emit(EventKind::kReconnect, e.t, {{EventField::kPort, std::string_view(e.port)}});
      } else {
        log_->emit(EventKind::kDisconnect, e.t,
                   {{EventField::kPort, std::string_view(e.port)},
                    {EventField::kReason, std::string_view(e.reason)}});
      }
    });
    if (recorder != nullptr) {
      recorder->set_file_listener([this](const std::string& path, Nanos t) {
        // The first file is where the recording starts, not a rotation.
        if (recorder_->files().size() > 1 || recorder_->reopens() > 0) {
          log_->emit(EventKind::kRotation, t, {{EventField::kFile, std::string_view(path)}});
        }
      });
    }
    arm_findings();
  }
  if (summary_every_ > 0) arm_summary();
}

void SessionMonitor::stop() {
  findings_timer_.cancel();
  summary_timer_.cancel();
  if (!log_ || capture_ == nullptr) return;
  const Nanos now = capture_->now();
  findings_->check(stats_, now);
  log_->emit(EventKind::kStop, now);
}

void SessionMonitor::arm_findings() {
  findings_timer_.expires_after(std::chrono::nanoseconds(kFindingsPeriod));
  findings_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    findings_->check(stats_, capture_->now());
    arm_findings();
  });
}

void SessionMonitor::arm_summary() {
  summary_timer_.expires_after(std::chrono::nanoseconds(summary_every_));
  summary_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    const Nanos now = capture_->now();
    const std::string text = summary_.write(stats_, now);
    if (recorder_ != nullptr) recorder_->add_comment(now, text);
    arm_summary();
  });
}

void SessionMonitor::reopen_events() {
  if (out_) out_->reopen();
}

}  // namespace rtu::app
