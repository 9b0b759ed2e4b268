// OutputStream's live delivery (keep_records_whole), read back through a real pipe: records
// arrive at flush, together, and never cut.
#include "core/output_stream.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <string>
#include <vector>

namespace rtu {
namespace {

class PipeReader {
 public:
  PipeReader() {
    EXPECT_EQ(::pipe2(fds_.data(), O_NONBLOCK), 0);
    // OutputStream writes to a path: the pipe's writing end, opened anew.
    path_ = "/dev/fd/" + std::to_string(fds_[1]);
  }
  ~PipeReader() {
    ::close(fds_[0]);
    ::close(fds_[1]);
  }
  PipeReader(const PipeReader&) = delete;
  PipeReader& operator=(const PipeReader&) = delete;

  [[nodiscard]] const std::string& path() const { return path_; }

  // What each read() returns until the pipe is empty: one entry per write that reached it,
  // as long as each write fits the pipe and none are pending together.
  std::vector<std::string> reads() {
    std::vector<std::string> out;
    std::array<char, 65536> buf{};
    for (;;) {
      const ssize_t n = ::read(fds_[0], buf.data(), buf.size());
      if (n <= 0) break;
      out.emplace_back(buf.data(), static_cast<std::size_t>(n));
    }
    return out;
  }
  std::string all() {
    std::string s;
    for (const auto& r : reads()) s += r;
    return s;
  }

 private:
  std::array<int, 2> fds_{};
  std::string path_;
};

fmt::memory_buffer record(char fill, std::size_t length) {
  fmt::memory_buffer b;
  for (std::size_t i = 0; i + 1 < length; ++i) b.push_back(fill);
  b.push_back('\n');
  return b;
}

TEST(OutputStream, WholeRecordsWaitForTheFlushAndArriveInOneWrite) {
  PipeReader pipe;
  OutputStream out(pipe.path());
  out.keep_records_whole();
  out.write(record('a', 300));
  out.write(record('b', 500));
  EXPECT_EQ(pipe.all(), "") << "records reach the file at flush, not one by one";
  out.flush();
  // A reader that polls between the writes would see one read per write: each flush is one.
  const auto reads = pipe.reads();
  ASSERT_EQ(reads.size(), 1U);
  EXPECT_EQ(reads[0], fmt::to_string(record('a', 300)) + fmt::to_string(record('b', 500)));
  out.flush();
  EXPECT_EQ(pipe.all(), "") << "a flush with nothing held writes nothing";
}

TEST(OutputStream, AHeldBatchThatWouldOutgrowOnePipeWriteIsWrittenAtARecordsEnd) {
  PipeReader pipe;
  OutputStream out(pipe.path());
  out.keep_records_whole();
  std::string expected;
  for (char c = 'a'; c < 'a' + 12; ++c) {  // 12 × 1000 bytes: more than one atomic write
    out.write(record(c, 1000));
    expected += fmt::to_string(record(c, 1000));
  }
  const std::string early = pipe.all();
  EXPECT_FALSE(early.empty()) << "more than 4096 bytes are not all held back";
  EXPECT_EQ(early.size() % 1000, 0U) << "written only at records' ends";
  EXPECT_LE(early.size(), 12000U - 1000U) << "the last record waits for the flush";
  out.flush();
  EXPECT_EQ(early + pipe.all(), expected);
}

TEST(OutputStream, ARecordLongerThanOnePipeWriteStillGoesOutWhole) {
  PipeReader pipe;
  OutputStream out(pipe.path());
  out.keep_records_whole();
  out.write(record('s', 10));
  out.write(record('L', 6000));
  out.flush();
  EXPECT_EQ(pipe.all(), fmt::to_string(record('s', 10)) + fmt::to_string(record('L', 6000)));
}

TEST(OutputStream, RecordsHeldWhenTheStreamIsDestroyedAreWritten) {
  PipeReader pipe;
  {
    OutputStream out(pipe.path());
    out.keep_records_whole();
    out.write(record('z', 64));
  }
  EXPECT_EQ(pipe.all(), fmt::to_string(record('z', 64)));
}

TEST(OutputStream, BufferedByDefaultAndWhatWasBufferedGoesFirstWhenKeptWhole) {
  PipeReader pipe;
  OutputStream out(pipe.path());
  out.write(record('1', 20));
  out.keep_records_whole();
  out.write(record('2', 20));
  EXPECT_EQ(pipe.all(), fmt::to_string(record('1', 20)));
  out.flush();
  EXPECT_EQ(pipe.all(), fmt::to_string(record('2', 20)));
}

}  // namespace
}  // namespace rtu
