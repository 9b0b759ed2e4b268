#include "capture/spooled_input.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "capture/open_capture.hpp"
#include "capture_test_files.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

using testing::read_all;
using testing::TempDir;

// A real pipe: `content` is written by another thread, as another process would.
class Pipe {
 public:
  explicit Pipe(std::string content) {
    int ends[2] = {-1, -1};
    EXPECT_EQ(::pipe(ends), 0);
    read_end_ = ends[0];
    writer_ = std::thread([fd = ends[1], text = std::move(content)] {
      std::size_t done = 0;
      while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
      }
      ::close(fd);
    });
  }
  ~Pipe() {
    writer_.join();
    ::close(read_end_);
  }
  Pipe(const Pipe&) = delete;
  Pipe& operator=(const Pipe&) = delete;
  [[nodiscard]] int fd() const { return read_end_; }

 private:
  int read_end_ = -1;
  std::thread writer_;
};

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string spool_error(int fd, const std::string& name, const SpoolOptions& options) {
  try {
    spool_input(fd, name, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

SpoolOptions in(const TempDir& dir) {
  SpoolOptions options;
  options.directory = dir.path().string();
  return options;
}

TEST(SpooledInput, APipeIsCopiedWholeReadableAsOftenAsNeededAndLeavesNoFile) {
  TempDir dir;
  std::string big;  // more than a pipe buffer and a copy buffer: several reads
  for (int i = 0; i < 40000; ++i) big += "0." + std::to_string(100000 + i) + " 01 03 00 00\n";
  Pipe pipe(big);
  const CaptureFile file = spool_input(pipe.fd(), "standard input", in(dir));
  EXPECT_EQ(file.name, "standard input");
  EXPECT_NE(file.path, file.name);
  // Every pass reads all of it, from the start, however many came before.
  EXPECT_EQ(contents(file.path), big);
  EXPECT_EQ(contents(file.path), big);
  // Already unlinked: nothing to clean up, whatever ends the run.
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(SpooledInput, TheCopyIsReadByTheRightReaderUnderTheInputsName) {
  TempDir dir;
  Pipe pipe("# baud=19200\n0.001 01 03\n0.002 zz\n");
  const CaptureFile file = spool_input(pipe.fd(), "standard input", in(dir));
  auto reader = open_capture(file, [](std::string_view) {});
  EXPECT_EQ(reader->name(), "standard input");
  try {
    read_all(*reader);
    FAIL() << "the bad line was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("standard input:3:", 0), 0U) << e.what();
  }
  ASSERT_TRUE(reader->declared_settings().has_value());
  EXPECT_EQ(reader->declared_settings()->baud, 19200U);
}

TEST(SpooledInput, AnEmptyInputIsAnError) {
  TempDir dir;
  Pipe pipe("");
  EXPECT_EQ(spool_error(pipe.fd(), "standard input", in(dir)),
            "standard input: empty input: nothing was written to it");
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(SpooledInput, AReadErrorSaysSoAndWhere) {
  TempDir dir;
  const int folder = ::open(dir.path().c_str(), O_RDONLY | O_CLOEXEC);
  ASSERT_GE(folder, 0);
  const std::string error = spool_error(folder, "cap.hex", in(dir));
  ::close(folder);
  EXPECT_EQ(error, "cap.hex: read error after 0 bytes: Is a directory");
}

TEST(SpooledInput, NoRoomForTheCopySaysWhereAndWhatToDo) {
  TempDir dir;
  std::string text;
  for (int i = 0; i < 2000; ++i) text += "0.5 01 03 00 00 00 0a c5 cd\n";
  Pipe pipe(text);
  // The file size limit fails writes as a full disk does, without needing one.
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = saved;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  const std::string error = spool_error(pipe.fd(), "standard input", in(dir));
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, previous);
  EXPECT_EQ(error.rfind("standard input: cannot keep a copy of the input in " +
                            dir.path().string() + " (after 4096 bytes): File too large",
                        0),
            0U)
      << error;
  EXPECT_NE(error.find("TMPDIR"), std::string::npos) << error;
}

TEST(SpooledInput, AMissingCopyFolderSaysWhich) {
  SpoolOptions options;
  options.directory = "/nonexistent-rtuscope-folder";
  Pipe pipe("0.5 01\n");
  EXPECT_EQ(spool_error(pipe.fd(), "standard input", options),
            "standard input: cannot make a temporary copy of the input in "
            "/nonexistent-rtuscope-folder: No such file or directory");
}

TEST(SpooledInput, TheTemporaryFolderIsTmpdir) {
  TempDir dir;
  const char* saved = std::getenv("TMPDIR");
  const std::string before = saved != nullptr ? saved : "";
  ::setenv("TMPDIR", "/nonexistent-rtuscope-tmpdir", 1);
  Pipe pipe("0.5 01\n");
  const std::string error = spool_error(pipe.fd(), "standard input", {});
  if (saved != nullptr) {
    ::setenv("TMPDIR", before.c_str(), 1);
  } else {
    ::unsetenv("TMPDIR");
  }
  EXPECT_NE(error.find("in /nonexistent-rtuscope-tmpdir:"), std::string::npos) << error;
}

TEST(SpooledInput, AFifoNobodyWritesToYetIsWaitedForWithAWord) {
  TempDir dir;
  const std::string fifo = (dir.path() / "capture.fifo").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&fifo] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    std::ofstream out(fifo, std::ios::binary);
    out << "0.5 01 03\n";
  });
  std::vector<std::string> said;
  SpoolOptions options;
  options.directory = dir.path().string();
  options.quiet_wait_ms = 50;
  options.on_waiting = [&said](const std::string& line) { said.push_back(line); };
  const CaptureFile file = spool_input(fifo, options);
  writer.join();
  EXPECT_EQ(file.name, fifo);
  EXPECT_EQ(contents(file.path), "0.5 01 03\n");
  ASSERT_EQ(said.size(), 1U);
  EXPECT_EQ(said[0], "waiting for " + fifo + " (nothing was written to it yet)");
}

TEST(SpooledInput, AFifoWhoseWriterClosesAtOnceIsEmpty) {
  TempDir dir;
  const std::string fifo = (dir.path() / "capture.fifo").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&fifo] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::ofstream out(fifo, std::ios::binary);
  });
  SpoolOptions options;
  options.directory = dir.path().string();
  std::string error;
  try {
    spool_input(fifo, options);
  } catch (const InputError& e) {
    error = e.what();
  }
  writer.join();
  EXPECT_EQ(error, fifo + ": empty input: nothing was written to it");
}

}  // namespace
}  // namespace rtu
