#pragma once
// SIGHUP during a live session: the recording goes on in a new file, for external log
// rotation (PcapngRecorder::reopen), and so does the event log (SessionMonitor). With neither
// the signal is ignored (it must not end a service that only serves metrics).
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <string>

#include "app/session_monitor.hpp"
#include "pipeline/live_capture.hpp"
#include "pipeline/pcapng_recorder.hpp"

namespace rtu::app {

class ReopenOnHangup {
 public:
  // Everything passed must outlive this; `recorder` and `monitor` may be null.
  ReopenOnHangup(boost::asio::io_context& io, LiveCapture& capture, PcapngRecorder* recorder,
                 SessionMonitor* monitor, std::string prefix);
  ~ReopenOnHangup();
  ReopenOnHangup(const ReopenOnHangup&) = delete;
  ReopenOnHangup& operator=(const ReopenOnHangup&) = delete;

 private:
  void arm();
  void reopen();

  boost::asio::signal_set signals_;
  LiveCapture& capture_;
  PcapngRecorder* recorder_;
  SessionMonitor* monitor_;
  std::string prefix_;
};

}  // namespace rtu::app
