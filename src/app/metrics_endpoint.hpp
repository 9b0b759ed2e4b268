#pragma once
// `--metrics ADDR:PORT` of a live session: the bus's metrics and the tool's health, served
// on the session's event loop. Each scrape reads the counters as they are between two
// records; nothing here runs on the path from a read to a printed frame.
#include <boost/asio/io_context.hpp>
#include <string>

#include "pipeline/live_capture.hpp"
#include "pipeline/metrics_server.hpp"
#include "pipeline/pcapng_recorder.hpp"
#include "report/bus_metrics.hpp"

namespace rtu::app {

class MetricsEndpoint {
 public:
  // Listens at `address` ("127.0.0.1:9464"); throws InputError naming --metrics when the
  // address is malformed or cannot be bound. Everything passed must outlive the endpoint;
  // `recorder` may be null (nothing recorded).
  MetricsEndpoint(boost::asio::io_context& io, const std::string& address,
                  const BusMetrics& metrics, LiveCapture& capture, const PcapngRecorder* recorder);

  // "http://127.0.0.1:9464/metrics", with the port actually bound.
  [[nodiscard]] std::string url() const;

 private:
  [[nodiscard]] ToolHealth health();

  const BusMetrics& metrics_;
  LiveCapture& capture_;
  const PcapngRecorder* recorder_;
  MetricsServer server_;
};

}  // namespace rtu::app
