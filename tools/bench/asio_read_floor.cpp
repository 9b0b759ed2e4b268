// The least CPU a program can use to hear a serial line through Boost.Asio's reactor, as
// `rtuscope live` does: an asynchronous read of the port for each batch it hands over, the
// bytes thrown away, nothing else. Between read_floor (a blocking read(), the kernel's own
// cost) and rtuscope, it tells what the reactor adds for each read: epoll_wait, and the
// speculative read that finds the port empty before each wait. tools/bench/live_cpu.py
// --asio-floor runs it where it would run `rtuscope live`.
//
//   asio_read_floor PORT   (stops on SIGINT or SIGTERM, and prints its reads and bytes)
#include <array>
#include <boost/asio/buffer.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <cstdio>

namespace {

namespace asio = boost::asio;

class Listener {
 public:
  Listener(asio::io_context& io, const char* path) : port_(io, path) {}

  void read_next() {
    port_.async_read_some(asio::buffer(buffer_),
                          [this](const boost::system::error_code& error, std::size_t n) {
                            if (error) return;
                            ++reads_;
                            bytes_ += n;
                            read_next();
                          });
  }
  void stop() {
    boost::system::error_code ignored;
    port_.close(ignored);
  }
  [[nodiscard]] unsigned long long reads() const { return reads_; }
  [[nodiscard]] unsigned long long bytes() const { return bytes_; }

 private:
  asio::serial_port port_;
  std::array<unsigned char, 4096> buffer_{};
  unsigned long long reads_ = 0;
  unsigned long long bytes_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: asio_read_floor PORT\n");
    return 2;
  }
  asio::io_context io;
  try {
    Listener listener(io, argv[1]);
    asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const boost::system::error_code& error, int /*signal*/) {
      if (!error) listener.stop();
    });
    listener.read_next();
    // One handler at a time, as rtuscope's live loop runs them.
    while (io.run_one() != 0 && !io.stopped()) {
    }
    std::fprintf(stderr, "read_floor: %llu reads, %llu bytes\n", listener.reads(),
                 listener.bytes());
  } catch (const boost::system::system_error& e) {
    std::fprintf(stderr, "asio_read_floor: %s: %s\n", argv[1], e.what());
    return 1;
  }
  return 0;
}
