#include "app/metrics_endpoint.hpp"

#include <fmt/format.h>

#include <cmath>

#include "report/prometheus_text.hpp"

namespace rtu::app {

MetricsEndpoint::MetricsEndpoint(boost::asio::io_context& io, const std::string& address,
                                 const BusMetrics& metrics, LiveCapture& capture,
                                 const PcapngRecorder* recorder)
    : metrics_(metrics),
      capture_(capture),
      recorder_(recorder),
      server_(
          io, parse_listen_address(address, "--metrics"),
          [this] {
            return MetricsServer::Page{std::string(ExpositionWriter::kContentType),
                                       metrics_.exposition(capture_.now(), health())};
          },
          "--metrics") {}

std::string MetricsEndpoint::url() const {
  const auto endpoint = server_.local_endpoint();
  const std::string host = endpoint.address().to_string();
  return endpoint.address().is_v6() ? fmt::format("http://[{}]:{}/metrics", host, endpoint.port())
                                    : fmt::format("http://{}:{}/metrics", host, endpoint.port());
}

ToolHealth MetricsEndpoint::health() {
  const LiveSummary& s = capture_.summary();
  ToolHealth h;
  h.read_bytes = s.bytes;
  h.disconnects = s.disconnects;
  h.reconnects = s.reconnects;
  if (s.last_byte_at != kUnknownTime) {
    h.seconds_since_last_byte = std::max(0.0, to_seconds(capture_.now() - s.last_byte_at));
  }
  if (recorder_ != nullptr) {
    h.recording = true;
    h.capture_bytes = recorder_->bytes_written();
    h.capture_files = recorder_->files().size();
    h.capture_reopens = recorder_->reopens();
  }
  return h;
}

}  // namespace rtu::app
