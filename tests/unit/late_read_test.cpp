// A live read the host made late (its thread busy, or waiting for a CPU) is marked, and its
// time is then no evidence of the silences next to it: the serial source measures it on a
// real pseudo-terminal, the recording keeps the mark, and a replay frames it the same way.
#include <gtest/gtest.h>
#include <pty.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <boost/asio/post.hpp>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "bus_builder.hpp"
#include "capture/rtac_serial.hpp"
#include "capture_test_files.hpp"
#include "core/issue.hpp"
#include "pipeline/pcapng_recorder.hpp"
#include "replayed_frames.hpp"
#include "serial/late_read_check.hpp"
#include "serial/serial_source.hpp"

namespace rtu {
namespace {

using test::export_raw;
using test::replayed_frames;
using testing::TempDir;

TEST(LateRead, SchedstatTextGivesTheTimeSpentWaitingForACpu) {
  EXPECT_EQ(parse_schedstat_run_delay("171528485 545766 3\n"), Nanos{545766});
  EXPECT_EQ(parse_schedstat_run_delay("0 0 0"), Nanos{0});
  EXPECT_FALSE(parse_schedstat_run_delay(""));
  EXPECT_FALSE(parse_schedstat_run_delay("12"));
  EXPECT_FALSE(parse_schedstat_run_delay("12 x 3"));
  EXPECT_FALSE(parse_schedstat_run_delay("-5 3 1"));
  EXPECT_FALSE(parse_schedstat_run_delay("12 34x 1"));
}

TEST(LateRead, TheThreadsCpuTimeGrowsWhileItComputesNotWhileItSleeps) {
  ThreadRunDelay run_delay;
  ASSERT_TRUE(run_delay.now()) << "no /proc/thread-self/schedstat";
  const Nanos before = thread_cpu_time();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const Nanos slept = thread_cpu_time();
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(20);
  while (std::chrono::steady_clock::now() < until) {
  }
  const Nanos spun = thread_cpu_time();
  EXPECT_LT(slept - before, 10 * kNanosPerMilli);
  // On a CPU most of the time (a loaded machine or a virtual one may take some of it).
  EXPECT_GE(spun - slept, 5 * kNanosPerMilli);
}

void spin_for(std::chrono::milliseconds how_long) {
  const auto until = std::chrono::steady_clock::now() + how_long;
  while (std::chrono::steady_clock::now() < until) {
  }
}

class Pty {
 public:
  Pty() {
    char name[128] = {};
    if (::openpty(&master_, &slave_, name, nullptr, nullptr) != 0) ADD_FAILURE() << "openpty";
    path_ = name;
  }
  ~Pty() {
    ::close(master_);
    ::close(slave_);
  }
  Pty(const Pty&) = delete;
  Pty& operator=(const Pty&) = delete;
  void write(std::uint8_t byte) const { ASSERT_EQ(::write(master_, &byte, 1), 1); }
  // Bytes the port holds unread (the kernel hands a write on to the port's reader a moment
  // later, from a worker thread).
  [[nodiscard]] int unread() const {
    int n = 0;
    return ::ioctl(slave_, FIONREAD, &n) == 0 ? n : 0;
  }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  int master_ = -1;
  int slave_ = -1;
  std::string path_;
};

// Where the reading thread is busy after the first read.
enum class BusyWhere : std::uint8_t {
  kInTheReadHandler,  // the read's handler itself spins
  kInALaterHandler,   // the read's handler returns at once (a quick handling); another spins
};

// Reads two one-byte reads through a real SerialSource: after the first, the thread spins
// for 5 ms (`where`), and the second byte is written before that (`second_while_busy`) or
// after it. Returns the two reads (their bytes left out).
std::vector<Chunk> two_reads(bool second_while_busy,
                             BusyWhere where = BusyWhere::kInTheReadHandler) {
  Pty pty;
  SystemClock clock;
  CaptureClock capture_clock(clock);
  boost::asio::io_context io;
  SerialConfig config;
  config.path = pty.path();
  config.line.baud = 9600;
  SerialSource source(io, capture_clock, config);
  source.open();
  std::vector<Chunk> reads;
  source.start(
      [&](const Chunk& chunk) {
        reads.push_back(chunk);
        reads.back().bytes = {};
        if (reads.size() != 1) return;
        const auto busy = [&pty, second_while_busy] {
          if (second_while_busy) {
            pty.write(0x22);
            // The byte waits in the port before the spin ends, however loaded the host.
            while (pty.unread() == 0) {
            }
          }
          spin_for(std::chrono::milliseconds(5));
        };
        if (where == BusyWhere::kInTheReadHandler) {
          busy();
        } else {
          boost::asio::post(io, busy);
        }
      },
      [](const std::error_code&) {});
  if (where == BusyWhere::kInALaterHandler) {
    // The first byte comes more than the 1 ms allowed after the read was issued, so its
    // completion reads the thread's CPU time, which the next read's moment then reuses.
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  pty.write(0x11);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  bool written = second_while_busy;
  while (reads.size() < 2 && std::chrono::steady_clock::now() < deadline) {
    io.run_one_for(std::chrono::milliseconds(10));
    if (!written && reads.size() == 1) {
      // The handler returned and the next read waits: the byte comes now.
      std::this_thread::sleep_for(std::chrono::milliseconds(3));
      pty.write(0x22);
      written = true;
    }
  }
  return reads;
}

TEST(LateRead, AByteThatArrivedWhileTheHandlerWasBusyIsReadLate) {
  const auto reads = two_reads(true);
  ASSERT_EQ(reads.size(), 2U);
  EXPECT_TRUE(reads[1].read_late);  // it waited out most of the 5 ms spin
  // The port was last seen empty when the first read was issued, before its byte came: not
  // when the second was, with its byte waiting.
  ASSERT_NE(reads[1].quiet_until, kUnknownTime);
  EXPECT_LE(reads[1].quiet_until, reads[0].t_end);
  // The first read is late too if a loaded host handled it long after its byte came; a read
  // on time carries no quiet moment.
  if (!reads[0].read_late) {
    EXPECT_EQ(reads[0].quiet_until, kUnknownTime);
  }
}

// The same after a quick handling, whose next read's moment reuses the CPU time read at the
// completion before it: the thread's work in another handler still bounds the read.
TEST(LateRead, AByteThatArrivedWhileAnotherHandlerWasBusyIsReadLate) {
  const auto reads = two_reads(true, BusyWhere::kInALaterHandler);
  ASSERT_EQ(reads.size(), 2U);
  EXPECT_TRUE(reads[1].read_late);
  // The port was last seen empty when the read was issued, before the byte was written and
  // the 5 ms spin began.
  ASSERT_NE(reads[1].quiet_until, kUnknownTime);
  EXPECT_GE(reads[1].quiet_until, reads[0].t_end);
  EXPECT_LE(reads[1].quiet_until + 5 * kNanosPerMilli, reads[1].t_end);
}

// The counterpart: the same busy handler, but the byte came after it, while the thread
// slept in the read's wait, and was taken at once. The thread's wake-up may itself be late
// on a loaded machine (then the mark is right), so one quiet try in a few suffices.
TEST(LateRead, AByteThatArrivedWhileTheReaderWaitedIsNotLate) {
  bool on_time = false;
  for (int attempt = 0; attempt < 5 && !on_time; ++attempt) {
    const auto reads = two_reads(false);
    ASSERT_EQ(reads.size(), 2U);
    on_time = !reads[1].read_late;
  }
  EXPECT_TRUE(on_time);
}

// 19200 baud: a character is 11 bits, 572,917 ns; t1.5 859 µs, t3.5 2.005 ms.
constexpr Nanos kChar = 572'917;
constexpr Nanos kT0 = 1'700'000'000 * kNanosPerSecond;
const std::vector<std::uint8_t> kRequest = {0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A};
const std::vector<std::uint8_t> kResponse = {0x01, 0x03, 0x02, 0x00, 0x2A, 0x39, 0x9B};

// The one port of a live recording: 19200 baud, read with a resolution of 1 ms.
void add_live_port(PcapngRecorder& recorder) {
  LineSettings line;
  line.baud = 19200;
  SerialStatus status;
  status.resolution = kNanosPerMilli;
  recorder.add_port(0, "/dev/ttyS0", line, status, 500 * kNanosPerMilli);
}

// A live recording of per-byte reads: the request's last byte read 4 ms late (`marked`
// says whether the source saw that), the response's bytes right after it.
std::string recording(const TempDir& dir, bool marked) {
  const std::string path = (dir.path() / (marked ? "late.pcapng" : "unmarked.pcapng")).string();
  PcapngRecorder recorder(path);
  add_live_port(recorder);
  Nanos t = kT0;
  const auto read = [&](std::uint8_t byte, bool late) {
    Chunk chunk;
    chunk.t_end = t;
    chunk.bytes = {&byte, 1};
    chunk.read_late = late;
    recorder.on_chunk(0, chunk);
  };
  for (std::size_t i = 0; i < kRequest.size(); ++i) {
    t += kChar;
    if (i + 1 == kRequest.size()) t += 4 * kNanosPerMilli;
    read(kRequest[i], marked && i + 1 == kRequest.size());
  }
  for (const std::uint8_t byte : kResponse) {
    t += kChar;
    read(byte, false);
  }
  recorder.on_end(t + kNanosPerSecond);
  recorder.flush();
  return path;
}

TEST(LateRead, ALateReadShowsNoPauseInItsFrameAndNoSilenceAfterIt) {
  TempDir dir;
  const auto path = recording(dir, true);
  for (const bool frame_ahead : {false, true}) {
    const auto frames = replayed_frames(path, frame_ahead);
    ASSERT_EQ(frames.size(), 2U) << "frame_ahead " << frame_ahead;
    EXPECT_TRUE(frames[0].crc_ok && frames[1].crc_ok);
    EXPECT_FALSE(frames[0].issues.has(IssueId::kT15)) << "frame_ahead " << frame_ahead;
    EXPECT_EQ(frames[1].gap_before, kUnknownTime) << "frame_ahead " << frame_ahead;
    EXPECT_FALSE(frames[1].issues.has(IssueId::kT35)) << "frame_ahead " << frame_ahead;
  }
}

// A raw export keeps the mark: decoding it gives the recording's frames.
TEST(LateRead, ARawExportKeepsTheMark) {
  TempDir dir;
  const auto path = recording(dir, true);
  const std::string exported = (dir.path() / "export.pcapng").string();
  export_raw(path, exported);
  const auto frames = replayed_frames(exported, false);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_FALSE(frames[0].issues.has(IssueId::kT15));
  EXPECT_EQ(frames[1].gap_before, kUnknownTime);
  EXPECT_FALSE(frames[1].issues.has(IssueId::kT35));
}

// The counterpart: the same times without the mark are what they say, a 4 ms pause inside
// the request and no silence before the response.
TEST(LateRead, TheSameTimesUnmarkedShowThePauseAndTheMissingSilence) {
  TempDir dir;
  const auto path = recording(dir, false);
  for (const bool frame_ahead : {false, true}) {
    const auto frames = replayed_frames(path, frame_ahead);
    ASSERT_EQ(frames.size(), 2U) << "frame_ahead " << frame_ahead;
    EXPECT_TRUE(frames[0].issues.has(IssueId::kT15)) << "frame_ahead " << frame_ahead;
    ASSERT_NE(frames[1].gap_before, kUnknownTime) << "frame_ahead " << frame_ahead;
    EXPECT_TRUE(frames[1].issues.has(IssueId::kT35)) << "frame_ahead " << frame_ahead;
  }
}

// Noise, a long quiet, then more noise in one late read whose port was seen empty 50 ms
// before it (`quiet_seen`), or with no such moment known: the recording of a live run.
std::string noise_recording(const TempDir& dir, bool quiet_seen) {
  const std::string path = (dir.path() / (quiet_seen ? "quiet.pcapng" : "unknown.pcapng")).string();
  PcapngRecorder recorder(path);
  add_live_port(recorder);
  const std::vector<std::uint8_t> noise = {0xFF, 0x00, 0xFE, 0x80, 0x7F};
  Nanos t = kT0;
  for (const std::uint8_t& byte : noise) {
    t += kChar;
    Chunk chunk;
    chunk.t_end = t;
    chunk.bytes = {&byte, 1};
    recorder.on_chunk(0, chunk);
  }
  t += 200 * kNanosPerMilli;
  Chunk late;
  late.t_end = t;
  late.bytes = noise;
  late.read_late = true;
  if (quiet_seen) late.quiet_until = t - 50 * kNanosPerMilli;
  recorder.on_chunk(0, late);
  recorder.on_end(t + kNanosPerSecond);
  recorder.flush();
  return path;
}

std::size_t noise_records(const std::vector<Record>& records) {
  std::size_t n = 0;
  for (const Record& r : records) n += r.kind == RecordKind::kNoise ? 1 : 0;
  return n;
}

// The line was seen quiet for far longer than t3.5 before the late read: the noise before
// it ended there, as a live run decided when its idle timer found the port empty. Its
// recording, and a raw export of that, keep the moment, and replay decides the same.
TEST(LateRead, AQuietMomentSeenBeforeALateReadEndsWhatCameBefore) {
  TempDir dir;
  const auto path = noise_recording(dir, true);
  const std::string exported = (dir.path() / "export.pcapng").string();
  export_raw(path, exported);
  for (const bool frame_ahead : {false, true}) {
    EXPECT_EQ(noise_records(test::replayed_records(path, frame_ahead)), 2U)
        << "frame_ahead " << frame_ahead;
  }
  EXPECT_EQ(noise_records(test::replayed_records(exported, false)), 2U);
}

// The counterpart: with no such moment, how long the line was quiet is not known (the
// bytes may have waited in the port all along), so the noise is one stretch.
TEST(LateRead, WithNoQuietMomentALateReadGoesOnWithWhatCameBefore) {
  TempDir dir;
  const auto path = noise_recording(dir, false);
  for (const bool frame_ahead : {false, true}) {
    EXPECT_EQ(noise_records(test::replayed_records(path, frame_ahead)), 1U)
        << "frame_ahead " << frame_ahead;
  }
}

TEST(LateRead, TheQuietMomentTravelsInTheReadsComment) {
  Chunk chunk;
  chunk.t_end = kT0;
  chunk.read_late = true;
  chunk.quiet_until = kT0 - 1'234'567;
  const std::string comment = time_marks_comment(time_marks_of(chunk, kT0));
  const ReadTimeMarks marks = time_marks_of(comment);
  EXPECT_TRUE(marks.read_late);
  EXPECT_FALSE(marks.time_clamped);
  EXPECT_EQ(marks.quiet_before, 1'234'567);
  // Only as written: a damaged number leaves the moment unknown, never another one.
  std::string damaged = comment;
  damaged.replace(damaged.find("1234567"), 7, "12x4567");
  EXPECT_EQ(time_marks_of(damaged).quiet_before, kUnknownTime);
  EXPECT_TRUE(time_marks_of(damaged).read_late);
}

}  // namespace
}  // namespace rtu
