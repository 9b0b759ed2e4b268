#include "app/reopen_on_hangup.hpp"

#include <fmt/format.h>

#include <csignal>
#include <utility>

#include "core/input_error.hpp"

namespace rtu::app {

ReopenOnHangup::ReopenOnHangup(boost::asio::io_context& io, LiveCapture& capture,
                               PcapngRecorder* recorder, std::string prefix)
    : signals_(io, SIGHUP), capture_(capture), recorder_(recorder), prefix_(std::move(prefix)) {
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
  if (recorder_ == nullptr || capture_.stopped()) return;
  try {
    recorder_->reopen(capture_.now());
    fmt::print(stderr, "{}: SIGHUP: recording on in {}\n", prefix_, recorder_->files().back());
  } catch (const InputError& e) {
    fmt::print(stderr, "{}: SIGHUP: {}; recording on in the file already open\n", prefix_,
               e.what());
  }
}

}  // namespace rtu::app
