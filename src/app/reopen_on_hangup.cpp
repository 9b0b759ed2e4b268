#include "app/reopen_on_hangup.hpp"

#include <fmt/format.h>

#include <csignal>
#include <utility>

#include "core/input_error.hpp"

namespace rtu::app {

ReopenOnHangup::ReopenOnHangup(boost::asio::io_context& io, LiveCapture& capture,
                               PcapngRecorder* recorder, SessionMonitor* monitor,
                               std::string prefix)
    : signals_(io, SIGHUP),
      capture_(capture),
      recorder_(recorder),
      monitor_(monitor),
      prefix_(std::move(prefix)) {
  arm();
}

ReopenOnHangup::~ReopenOnHangup() {
  boost::system::error_code ignored;
  signals_.cancel(ignored);
}

void ReopenOnHangup::arm() {
  signals_.async_wait([this](const boost::system::error_code& ec, int) {
    if (ec) return;
    reopen();
    arm();
  });
}

void ReopenOnHangup::reopen() {
  if (capture_.stopped()) return;
  if (monitor_ != nullptr) {
    try {
      monitor_->reopen_events();
    } catch (const InputError& e) {
      fmt::print(stderr, "{}: SIGHUP: {}; events go on in the file already open\n", prefix_,
                 e.what());
    }
  }
  if (recorder_ == nullptr) return;
  try {
    recorder_->reopen(capture_.now());
    fmt::print(stderr, "{}: SIGHUP: recording on in {}\n", prefix_, recorder_->files().back());
  } catch (const InputError& e) {
    fmt::print(stderr, "{}: SIGHUP: {}; recording on in the file already open\n", prefix_,
               e.what());
  }
}

}  // namespace rtu::app
