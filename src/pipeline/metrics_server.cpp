// GCC 12 reports a "potential null pointer dereference" inside Asio's scheduler once the
// socket handlers of this file are inlined at -O2 (boost/asio/detail/impl/scheduler.ipp:325,
// a thread-info pointer Asio has checked before use): a false alarm in Asio's code, not ours.
// It must be silenced before the first Asio header, which our own header includes.
#pragma GCC diagnostic ignored "-Wnull-dereference"

#include "pipeline/metrics_server.hpp"

#include <fmt/format.h>

#include <boost/asio/read_until.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/write.hpp>
#include <charconv>
#include <chrono>
#include <istream>
#include <utility>

#include "core/input_error.hpp"

namespace rtu {

namespace asio = boost::asio;
using asio::ip::tcp;

struct MetricsServer::Shared {
  Render render;
  std::size_t open_connections = 0;
  std::uint64_t scrapes = 0;
};

namespace {

constexpr std::size_t kMaxHeaderBytes = 8192;
constexpr std::size_t kMaxConnections = 16;
constexpr std::chrono::seconds kRequestDeadline{10};

std::string http_response(std::string_view status, std::string_view content_type,
                          std::string_view body) {
  return fmt::format(
      "HTTP/1.1 {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{}",
      status, content_type, body.size(), body);
}

// One connection: reads the request head, answers, closes.
class Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(tcp::socket socket, std::shared_ptr<MetricsServer::Shared> shared)
      : socket_(std::move(socket)),
        deadline_(socket_.get_executor()),
        buffer_(kMaxHeaderBytes),
        shared_(std::move(shared)) {
    ++shared_->open_connections;
  }
  ~Connection() { --shared_->open_connections; }
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  void start() {
    auto self = shared_from_this();
    deadline_.expires_after(kRequestDeadline);
    deadline_.async_wait([self](const boost::system::error_code& ec) {
      if (!ec) self->close();
    });
    asio::async_read_until(socket_, buffer_, "\r\n\r\n",
                           [self](const boost::system::error_code& ec, std::size_t) {
                             if (ec) {
                               self->close();
                               return;
                             }
                             self->answer();
                           });
  }

 private:
  void answer() {
    std::istream head(&buffer_);
    std::string method;
    std::string target;
    head >> method >> target;
    const std::string_view path = std::string_view(target).substr(0, target.find('?'));
    if (method != "GET" && method != "HEAD") {
      reply_ = http_response("405 Method Not Allowed", "text/plain", "GET only\n");
    } else if (path == "/metrics" && shared_->render) {
      ++shared_->scrapes;
      const MetricsServer::Page page = shared_->render();
      reply_ = http_response("200 OK", page.content_type, method == "HEAD" ? "" : page.body);
    } else {
      reply_ = http_response("404 Not Found", "text/plain", "rtuscope serves /metrics\n");
    }
    auto self = shared_from_this();
    asio::async_write(socket_, asio::buffer(reply_),
                      [self](const boost::system::error_code&, std::size_t) { self->close(); });
  }

  void close() {
    deadline_.cancel();
    boost::system::error_code ignored;
    socket_.shutdown(tcp::socket::shutdown_both, ignored);
    socket_.close(ignored);
  }

  tcp::socket socket_;
  asio::steady_timer deadline_;
  asio::streambuf buffer_;
  std::string reply_;
  std::shared_ptr<MetricsServer::Shared> shared_;
};

}  // namespace

ListenAddress parse_listen_address(std::string_view text, std::string_view option) {
  const auto bad = [&](std::string_view why) {
    return InputError(
        fmt::format("{} {}: {} (expected ADDRESS:PORT, e.g. 127.0.0.1:9464 or "
                    "[::1]:9464)",
                    option, text, why));
  };
  const std::size_t colon = text.rfind(':');
  if (colon == std::string_view::npos) throw bad("no port");
  std::string_view host = text.substr(0, colon);
  const std::string_view port_text = text.substr(colon + 1);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  } else if (host.find(':') != std::string_view::npos) {
    throw bad("an IPv6 address goes in brackets");
  }
  if (host.empty()) throw bad("no address (use 0.0.0.0 to listen everywhere)");
  unsigned port = 0;
  const auto [end, ec] =
      std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  if (port_text.empty() || ec != std::errc() || end != port_text.data() + port_text.size() ||
      port > 65535) {
    throw bad(fmt::format("port '{}' is not a number from 0 to 65535", port_text));
  }
  boost::system::error_code parse_error;
  asio::ip::make_address(std::string(host), parse_error);
  if (parse_error) throw bad(fmt::format("'{}' is not an IP address", host));
  return ListenAddress{std::string(host), static_cast<std::uint16_t>(port)};
}

MetricsServer::MetricsServer(asio::io_context& io, const ListenAddress& address, Render render,
                             std::string_view option)
    : acceptor_(io), shared_(std::make_shared<Shared>()) {
  shared_->render = std::move(render);
  const tcp::endpoint endpoint(asio::ip::make_address(address.host), address.port);
  boost::system::error_code ec;
  acceptor_.open(endpoint.protocol(), ec);
  if (!ec) acceptor_.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor_.bind(endpoint, ec);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    throw InputError(fmt::format("{} {}:{}: cannot listen: {}", option, address.host, address.port,
                                 ec.message()));
  }
  accept();
}

MetricsServer::~MetricsServer() {
  shared_->render = nullptr;  // connections still open answer 404 from now on
  boost::system::error_code ignored;
  acceptor_.close(ignored);
}

tcp::endpoint MetricsServer::local_endpoint() const {
  return acceptor_.local_endpoint();
}

std::uint64_t MetricsServer::scrapes() const {
  return shared_->scrapes;
}

void MetricsServer::accept() {
  acceptor_.async_accept([this](const boost::system::error_code& ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted) return;  // closed: the server is gone
    if (!ec && shared_->open_connections < kMaxConnections) {
      std::make_shared<Connection>(std::move(socket), shared_)->start();
    }
    accept();
  });
}

}  // namespace rtu
