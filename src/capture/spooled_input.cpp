#include "capture/spooled_input.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "core/input_error.hpp"

namespace rtu {
namespace {

constexpr std::size_t kCopyBufferSize = 256U * 1024U;

std::string copy_directory(const SpoolOptions& options) {
  if (!options.directory.empty()) return options.directory;
  const char* tmpdir = std::getenv("TMPDIR");
  return tmpdir != nullptr && *tmpdir != '\0' ? std::string(tmpdir) : std::string("/tmp");
}

// The temporary copy. Unlinked as soon as it exists, it is reopened by each pass through
// /proc/self/fd (every open has its own offset, so passes never disturb each other) and
// vanishes when its descriptor closes. Without /proc it keeps its name until then.
class SpoolFile {
 public:
  SpoolFile(const std::string& directory, const std::string& name) {
    std::string path = directory + "/rtuscope-input-XXXXXX";
    fd_ = ::mkostemp(path.data(), O_CLOEXEC);
    if (fd_ < 0) {
      throw InputError(fmt::format("{}: cannot make a temporary copy of the input in {}: {}", name,
                                   directory, std::strerror(errno)));
    }
    const std::string by_descriptor = fmt::format("/proc/self/fd/{}", fd_);
    if (::access(by_descriptor.c_str(), R_OK) == 0) {
      ::unlink(path.c_str());
      path_ = by_descriptor;
    } else {
      path_ = path;
      linked_ = true;
    }
  }
  ~SpoolFile() {
    if (linked_) ::unlink(path_.c_str());
    ::close(fd_);
  }
  SpoolFile(const SpoolFile&) = delete;
  SpoolFile& operator=(const SpoolFile&) = delete;

  [[nodiscard]] int fd() const { return fd_; }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  int fd_ = -1;
  std::string path_;
  bool linked_ = false;
};

// Closes a descriptor this file opened.
class OpenedFd {
 public:
  explicit OpenedFd(int fd) : fd_(fd) {}
  ~OpenedFd() {
    if (fd_ >= 0) ::close(fd_);
  }
  OpenedFd(const OpenedFd&) = delete;
  OpenedFd& operator=(const OpenedFd&) = delete;
  [[nodiscard]] int get() const { return fd_; }

 private:
  int fd_;
};

// Returns once `fd` has data or its end; says what it waits for if that takes a while.
void wait_for_input(int fd, const std::string& name, const SpoolOptions& options) {
  pollfd wanted{fd, POLLIN, 0};
  int timeout_ms = options.quiet_wait_ms;
  for (;;) {
    const int ready = ::poll(&wanted, 1, timeout_ms);
    if (ready > 0) return;
    if (ready < 0 && errno != EINTR) return;  // the read that follows says what is wrong
    if (ready == 0) {
      if (options.on_waiting) {
        options.on_waiting(fmt::format("waiting for {} (nothing was written to it yet)", name));
      }
      timeout_ms = -1;
    }
  }
}

void write_all(const SpoolFile& copy, const char* data, std::size_t size, std::uint64_t done,
               const std::string& name, const std::string& directory) {
  while (size > 0) {
    const ssize_t written = ::write(copy.fd(), data, size);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      const int error = written < 0 ? errno : ENOSPC;
      throw InputError(fmt::format(
          "{}: cannot keep a copy of the input in {} (after {} bytes): {}; set TMPDIR to a "
          "directory with room for the whole capture",
          name, directory, done, std::strerror(error)));
    }
    const auto n = static_cast<std::size_t>(written);
    data += n;
    size -= n;
    done += n;
  }
}

}  // namespace

CaptureFile spool_input(int fd, const std::string& name, const SpoolOptions& options) {
  const std::string directory = copy_directory(options);
  auto copy = std::make_shared<SpoolFile>(directory, name);
  std::vector<char> buffer(kCopyBufferSize);
  std::uint64_t total = 0;
  wait_for_input(fd, name, options);
  for (;;) {
    const ssize_t got = ::read(fd, buffer.data(), buffer.size());
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      wait_for_input(fd, name, options);
      continue;
    }
    if (got < 0) {
      throw InputError(
          fmt::format("{}: read error after {} bytes: {}", name, total, std::strerror(errno)));
    }
    if (got == 0) break;
    const auto n = static_cast<std::size_t>(got);
    write_all(*copy, buffer.data(), n, total, name, directory);
    total += n;
  }
  if (total == 0) throw InputError(fmt::format("{}: empty input: nothing was written to it", name));
  const std::string path = copy->path();
  return CaptureFile(path, name, std::move(copy));
}

CaptureFile spool_input(const std::string& path, const SpoolOptions& options) {
  // Not blocking: opening a FIFO would otherwise wait, without a word, for a writer.
  const OpenedFd input(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (input.get() < 0) {
    throw InputError(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  }
  wait_for_input(input.get(), path, options);
  // From here on, reads wait for the writer as any pipe's do.
  const int flags = ::fcntl(input.get(), F_GETFL);
  if (flags >= 0) ::fcntl(input.get(), F_SETFL, flags & ~O_NONBLOCK);
  return spool_input(input.get(), path, options);
}

}  // namespace rtu
