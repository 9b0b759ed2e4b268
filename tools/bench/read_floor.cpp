// The least CPU any program can use to hear a serial line: a blocking read() for each batch
// the port hands over, the bytes thrown away, nothing else. tools/bench/live_cpu.py --floor
// runs it where it would run `rtuscope live`, so that rtuscope's share of a core can be read
// against what the kernel alone costs for the same reads on the same machine.
//
//   read_floor PORT        (stops on SIGINT or SIGTERM, and prints its reads and bytes)
#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

namespace {

volatile std::sig_atomic_t stop = 0;

void on_signal(int /*signal*/) {
  stop = 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: read_floor PORT\n");
    return 2;
  }
  const int fd = ::open(argv[1], O_RDONLY | O_NOCTTY);
  if (fd < 0) {
    std::fprintf(stderr, "read_floor: %s: %s\n", argv[1], std::strerror(errno));
    return 1;
  }
  termios tio{};
  if (::tcgetattr(fd, &tio) == 0) {
    ::cfmakeraw(&tio);
    tio.c_cc[VMIN] = 1;  // return as soon as a byte is there, as rtuscope's reads do
    tio.c_cc[VTIME] = 0;
    ::tcsetattr(fd, TCSANOW, &tio);
  }
  struct sigaction action {};
  action.sa_handler = on_signal;  // no SA_RESTART: the blocked read() returns at once
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
  std::array<unsigned char, 4096> buffer{};
  unsigned long long reads = 0;
  unsigned long long bytes = 0;
  while (stop == 0) {
    const ssize_t n = ::read(fd, buffer.data(), buffer.size());
    if (n > 0) {
      ++reads;
      bytes += static_cast<unsigned long long>(n);
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  std::fprintf(stderr, "read_floor: %llu reads, %llu bytes\n", reads, bytes);
  ::close(fd);
  return 0;
}
