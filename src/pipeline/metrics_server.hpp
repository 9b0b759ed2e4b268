#pragma once
// The `--metrics ADDR:PORT` endpoint: a minimal HTTP/1.1 server on the capture's own Asio
// event loop that answers `GET /metrics` with the text a callback renders (Prometheus'
// exposition format). It never reads a clock or touches the capture: the callback runs
// between two handlers of the loop, so it sees the counters of records already produced
// and needs no lock, and framing never waits for it beyond that one call.
//
// One request per connection (the answer closes it, as Prometheus expects nothing more);
// requests are bounded (8 KiB of header, 10 s to send it) and so are open connections (16),
// so a stuck or hostile client costs nothing but its own socket.
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace rtu {

struct ListenAddress {
  std::string host;  // an IPv4 or IPv6 address ("127.0.0.1", "::1")
  std::uint16_t port = 0;
};

// "127.0.0.1:9464", "[::1]:9464", "0.0.0.0:9464" → an address. Throws InputError naming
// `option` and what is wrong when the text is not one.
ListenAddress parse_listen_address(std::string_view text, std::string_view option);

class MetricsServer {
 public:
  // The body and its Content-Type, rendered at each scrape.
  struct Page {
    std::string content_type;
    std::string body;
  };
  using Render = std::function<Page()>;

  // Listens at once. Throws InputError naming `option` when the address cannot be bound.
  MetricsServer(boost::asio::io_context& io, const ListenAddress& address, Render render,
                std::string_view option);
  ~MetricsServer();
  MetricsServer(const MetricsServer&) = delete;
  MetricsServer& operator=(const MetricsServer&) = delete;

  // The address and port listened on (the port chosen by the system when 0 was asked for).
  [[nodiscard]] boost::asio::ip::tcp::endpoint local_endpoint() const;
  [[nodiscard]] std::uint64_t scrapes() const;

  struct Shared;  // what connections share with the server (implementation detail)

 private:
  void accept();

  boost::asio::ip::tcp::acceptor acceptor_;
  std::shared_ptr<Shared> shared_;
};

}  // namespace rtu
