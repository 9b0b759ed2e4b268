// The Asio serial source over real pseudo-terminals: bytes written on the master side
// arrive on the slave side, through the same configuration and read path as a real port.
#include "serial/serial_source.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "serial/custom_baud.hpp"

namespace rtu {
namespace {

// Every reading is 1 ms after the previous one; wall = monotonic + a fixed offset.
class SteppingClock final : public Clock {
 public:
  ClockReading now() override {
    mono_ += kNanosPerMilli;
    ++readings;
    return {mono_, mono_ + kWallOffset};
  }
  static constexpr Nanos kWallOffset = 1'700'000'000 * kNanosPerSecond;
  int readings = 0;

 private:
  Nanos mono_ = 5 * kNanosPerSecond;
};

class Pty {
 public:
  Pty() {
    char name[128] = {};
    if (::openpty(&master_, &slave_, name, nullptr, nullptr) != 0) {
      ADD_FAILURE() << "openpty failed";
    }
    path_ = name;
  }
  ~Pty() {
    if (master_ >= 0) ::close(master_);
    if (slave_ >= 0) ::close(slave_);
  }
  Pty(const Pty&) = delete;
  Pty& operator=(const Pty&) = delete;

  // Raw mode on the slave side before the source opens it, as a port left by a reader before:
  // the pty's default line discipline would take control bytes (0x03 interrupts and flushes).
  void make_raw() const {
    termios t{};
    ASSERT_EQ(::tcgetattr(slave_, &t), 0);
    ::cfmakeraw(&t);
    ASSERT_EQ(::tcsetattr(slave_, TCSANOW, &t), 0);
  }
  void write(const std::vector<std::uint8_t>& bytes) const {
    ASSERT_EQ(::write(master_, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
  }
  void close_master() {
    ::close(master_);
    master_ = -1;
    // Keep no slave descriptor of our own, or the source would never see the hang-up.
    ::close(slave_);
    slave_ = -1;
  }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  int master_ = -1;
  int slave_ = -1;
  std::string path_;
};

struct Received {
  std::vector<std::uint8_t> bytes;
  std::vector<std::uint8_t> errors;
  std::vector<Nanos> times;
  std::error_code error;
};

// Runs the io_context until `done` or a generous I/O deadline (not a timing assertion).
template <typename Done>
void run_until(boost::asio::io_context& io, Done done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    io.run_one_for(std::chrono::milliseconds(50));
  }
}

SerialConfig config_for(const Pty& pty, std::uint32_t baud = 19200, Parity parity = Parity::kEven) {
  SerialConfig c;
  c.path = pty.path();
  c.line.baud = baud;
  c.line.parity = parity;
  return c;
}

void start_collecting(SerialSource& source, Received& rx) {
  source.start(
      [&rx](const Chunk& chunk) {
        for (std::size_t i = 0; i < chunk.bytes.size(); ++i) {
          rx.bytes.push_back(chunk.bytes[i]);
          rx.errors.push_back(chunk.errors.empty() ? std::uint8_t{kLineOk} : chunk.errors[i]);
        }
        rx.times.push_back(chunk.t_end);
      },
      [&rx](const std::error_code& ec) { rx.error = ec; });
}

TEST(SerialSource, BytesWrittenOnTheMasterArriveWithFFMarksDecoded) {
  Pty pty;
  SteppingClock clock;
  CaptureClock capture_clock(clock);
  boost::asio::io_context io;
  SerialSource source(io, capture_clock, config_for(pty));
  const SerialStatus& status = source.open();
  EXPECT_TRUE(status.error_marking);
  EXPECT_FALSE(status.counters);        // a pty has no TIOCGICOUNT
  EXPECT_FALSE(status.parity_applied);  // nor parity, which is said once, not fatal
  ASSERT_EQ(status.notes.size(), 1U);
  EXPECT_NE(status.notes[0].find("parity"), std::string::npos);

  Received rx;
  start_collecting(source, rx);
  // With PARMRK the tty doubles the FF bytes; the decoder must undo exactly that.
  const std::vector<std::uint8_t> frame = {0x01, 0xFF, 0x00, 0xFF, 0xFF, 0x7E, 0x00, 0x03};
  pty.write(frame);
  run_until(io, [&] { return rx.bytes.size() >= frame.size(); });
  EXPECT_EQ(rx.bytes, frame);
  EXPECT_EQ(rx.errors, std::vector<std::uint8_t>(frame.size(), kLineOk));
  ASSERT_FALSE(rx.times.empty());
  // Stamps are capture times: anchored on the wall clock, one reading per read completion.
  for (const Nanos t : rx.times) {
    EXPECT_GT(t, SteppingClock::kWallOffset);
    EXPECT_EQ((t - SteppingClock::kWallOffset) % kNanosPerMilli, 0);
  }
}

TEST(SerialSource, ChunkTimeIsTheClockReadAtReadCompletion) {
  Pty pty;
  SteppingClock clock;
  CaptureClock capture_clock(clock);  // one reading: the anchor
  boost::asio::io_context io;
  SerialSource source(io, capture_clock, config_for(pty));
  source.open();
  Received rx;
  start_collecting(source, rx);
  pty.write({0x11, 0x22});
  run_until(io, [&] { return rx.bytes.size() >= 2; });
  ASSERT_EQ(rx.times.size(), 1U);
  // Anchor at mono 5.001 s; the moment the read was issued with no input pending is the
  // next reading (a late read would carry it), and the read is stamped with the one after.
  EXPECT_EQ(rx.times[0], SteppingClock::kWallOffset + 5 * kNanosPerSecond + 3 * kNanosPerMilli);
}

// Bytes that waited in the port before it was opened came at times nothing tells: the read
// that takes them is marked late with no quiet moment known, so no silence is measured next
// to them (a replay of a rotation set would otherwise measure one from the recording
// before). The reads after it are judged as usual.
TEST(SerialSource, BytesWaitingWhenThePortOpensAreReadAsLate) {
  Pty pty;
  pty.make_raw();
  pty.write({0x11, 0x03, 0x00});  // before the source opens the port
  SteppingClock clock;
  CaptureClock capture_clock(clock);
  boost::asio::io_context io;
  SerialSource source(io, capture_clock, config_for(pty));
  source.open();
  std::vector<Chunk> chunks;
  std::vector<std::vector<std::uint8_t>> bytes;
  source.start(
      [&](const Chunk& chunk) {
        chunks.push_back(chunk);
        bytes.emplace_back(chunk.bytes.begin(), chunk.bytes.end());
      },
      [](const std::error_code&) {});
  run_until(io, [&] { return !chunks.empty(); });
  ASSERT_EQ(chunks.size(), 1U);
  EXPECT_EQ(bytes[0], (std::vector<std::uint8_t>{0x11, 0x03, 0x00}));
  EXPECT_TRUE(chunks[0].read_late);
  EXPECT_EQ(chunks[0].quiet_until, kUnknownTime);
  pty.write({0x00});
  run_until(io, [&] { return chunks.size() >= 2; });
  ASSERT_EQ(chunks.size(), 2U);
  EXPECT_FALSE(chunks[1].read_late);
}

TEST(SerialSource, NonStandardBaudRateIsSetExactly) {
  Pty pty;
  SteppingClock clock;
  CaptureClock capture_clock(clock);
  boost::asio::io_context io;
  SerialSource source(io, capture_clock, config_for(pty, 76800, Parity::kNone));
  const SerialStatus& status = source.open();
  EXPECT_EQ(status.baud, 76800U);
  EXPECT_TRUE(status.error_marking);
  EXPECT_TRUE(status.notes.empty());
}

TEST(SerialSource, StandardBaudRateAndTwoStopBits) {
  Pty pty;
  SteppingClock clock;
  CaptureClock capture_clock(clock);
  boost::asio::io_context io;
  SerialConfig config = config_for(pty, 9600, Parity::kNone);
  config.line.stop_bits = 2;
  SerialSource source(io, capture_clock, config);
  EXPECT_EQ(source.open().baud, 9600U);
}

TEST(SerialSource, HangUpIsReportedAsAnError) {
  Pty pty;
  SteppingClock clock;
  CaptureClock capture_clock(clock);
  boost::asio::io_context io;
  SerialSource source(io, capture_clock, config_for(pty));
  source.open();
  Received rx;
  start_collecting(source, rx);
  pty.write({0x01, 0x02});
  run_until(io, [&] { return rx.bytes.size() >= 2; });
  pty.close_master();
  run_until(io, [&] { return static_cast<bool>(rx.error); });
  EXPECT_TRUE(static_cast<bool>(rx.error));
  EXPECT_FALSE(source.is_open());
  EXPECT_EQ(rx.bytes, std::vector<std::uint8_t>({0x01, 0x02}));
}

TEST(SerialSource, MissingPortIsAClearError) {
  SteppingClock clock;
  CaptureClock capture_clock(clock);
  boost::asio::io_context io;
  SerialConfig config;
  config.path = "/dev/ttyDOESNOTEXIST9";
  SerialSource source(io, capture_clock, config);
  try {
    source.open();
    FAIL() << "expected SerialOpenError";
  } catch (const SerialOpenError& e) {
    EXPECT_NE(std::string(e.what()).find("no such serial port"), std::string::npos);
    EXPECT_EQ(e.code().value(), ENOENT);
  }
}

TEST(SerialSource, AFileThatIsNoPortIsRefused) {
  SteppingClock clock;
  CaptureClock capture_clock(clock);
  boost::asio::io_context io;
  SerialConfig config;
  config.path = "/dev/null";
  SerialSource source(io, capture_clock, config);
  EXPECT_THROW(source.open(), SerialOpenError);
}

}  // namespace
}  // namespace rtu
