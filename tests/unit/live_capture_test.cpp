// Live capture end to end over the virtual bus: real pseudo-terminals, the real Asio
// source, the decode pipeline, and the pcapng recorder. The waits below wait for I/O to
// happen (with a generous deadline); nothing asserts on how long anything took.
#include "pipeline/live_capture.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "capture/pcap_reader.hpp"
#include "capture/rtac_serial.hpp"
#include "pipeline/pcapng_recorder.hpp"
#include "pipeline/replay.hpp"
#include "serial/virtual_bus.hpp"

namespace rtu {
namespace {

using test::CollectingSink;
using test::with_crc;

template <typename Done>
bool run_until(boost::asio::io_context& io, Done done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    io.run_one_for(std::chrono::milliseconds(20));
  }
  return done();
}

bool said(const std::vector<std::string>& notes, const std::string& what) {
  for (const auto& n : notes) {
    if (n.find(what) != std::string::npos) return true;
  }
  return false;
}

class LiveCaptureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("rtuscope_live_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

// Broadcast writes: no response is expected, so each frame is released as soon as the
// line has been quiet for t3.5.
const std::vector<std::uint8_t> kFirst = with_crc({0x00, 0x06, 0x00, 0x01, 0x00, 0x03});
const std::vector<std::uint8_t> kSecond = with_crc({0x00, 0x06, 0x00, 0x02, 0xFF, 0xFF});

TEST_F(LiveCaptureTest, FramesArePrintedWhenTheLineGoesQuietAndRecorded) {
  VirtualBusOptions bus_options;
  bus_options.line = LineSettings{19200, Parity::kEven, 1};
  VirtualBus bus(bus_options);
  bus.start();
  const std::string file = (dir_ / "live.pcapng").string();
  PcapngRecorder recorder(file);
  CollectingSink sink;
  std::vector<std::string> notes;
  LiveOptions options;
  options.ports = {bus.paths()[2]};
  options.line = bus_options.line;
  boost::asio::io_context io;
  SystemClock clock;
  LiveCapture capture(io, clock, options, sink, &recorder,
                      [&](const std::string& m) { notes.push_back(m); });
  capture.start();
  EXPECT_TRUE(said(notes, "parity"));  // a pty has none: said, not fatal
  const int master = open_bus_endpoint(bus.paths()[0]);
  ASSERT_EQ(::write(master, kFirst.data(), kFirst.size()), 8);
  // No more bytes come: only the idle timer can decide the frame.
  ASSERT_TRUE(run_until(io, [&] { return sink.records.size() >= 1; }));
  ASSERT_EQ(::write(master, kSecond.data(), kSecond.size()), 8);
  ASSERT_TRUE(run_until(io, [&] { return sink.records.size() >= 2; }));
  capture.stop();
  ::close(master);
  bus.stop();

  ASSERT_EQ(sink.records.size(), 2U);
  EXPECT_EQ(
      std::vector<std::uint8_t>(sink.records[0].bytes().begin(), sink.records[0].bytes().end()),
      kFirst);
  EXPECT_EQ(
      std::vector<std::uint8_t>(sink.records[1].bytes().begin(), sink.records[1].bytes().end()),
      kSecond);
  EXPECT_TRUE(sink.records[1].crc_ok);  // its FF bytes survived PARMRK doubling
  EXPECT_EQ(capture.summary().frames, 2U);
  EXPECT_EQ(capture.summary().bytes, 16U);

  // The file holds exactly the bytes read, on a LINKTYPE 250 interface that declares the
  // line settings and the timing resolution, then the end of the capture.
  PcapReader reader(file);
  CapturePacket packet;
  std::vector<std::uint8_t> recorded;
  std::vector<std::uint8_t> events;
  while (reader.next(packet)) {
    EXPECT_EQ(packet.link_type, 250);
    EXPECT_NE(packet.interface_description.find("19200 8E1"), std::string::npos);
    EXPECT_NE(packet.interface_description.find("timing resolution 1 ms"), std::string::npos);
    EXPECT_NE(packet.interface_description.find("response timeout 1000 ms"), std::string::npos);
    EXPECT_EQ(packet.interface_name, bus.paths()[2]);
    std::string error;
    const auto rec = parse_rtac_record(packet.data, error);
    ASSERT_TRUE(rec.has_value()) << error;
    events.push_back(rec->event);
    recorded.insert(recorded.end(), rec->payload.begin(), rec->payload.end());
  }
  ASSERT_EQ(events.size(), capture.summary().chunks + 1);
  EXPECT_EQ(events.back(), static_cast<std::uint8_t>(RtacEvent::kCaptureComplete));
  events.pop_back();
  for (const std::uint8_t e : events) {
    EXPECT_EQ(e, static_cast<std::uint8_t>(RtacEvent::kDataRxStart));
  }
  std::vector<std::uint8_t> both = kFirst;
  both.insert(both.end(), kSecond.begin(), kSecond.end());
  EXPECT_EQ(recorded, both);
}

TEST_F(LiveCaptureTest, UnpluggedPortIsReopenedAndTheGapIsRecorded) {
  VirtualBusOptions bus_options;
  bus_options.line = LineSettings{19200, Parity::kNone, 1};
  bus_options.link_dir = (dir_ / "links").string();
  VirtualBus bus(bus_options);
  bus.start();
  const std::string file = (dir_ / "gap.pcapng").string();
  PcapngRecorder recorder(file);
  CollectingSink sink;
  std::vector<std::string> notes;
  LiveOptions options;
  options.ports = {bus.paths()[2]};
  options.line = bus_options.line;
  options.reopen_period = 20 * kNanosPerMilli;
  boost::asio::io_context io;
  SystemClock clock;
  LiveCapture capture(io, clock, options, sink, &recorder,
                      [&](const std::string& m) { notes.push_back(m); });
  capture.start();
  const int master = open_bus_endpoint(bus.paths()[0]);
  ASSERT_EQ(::write(master, kFirst.data(), kFirst.size()), 8);
  ASSERT_TRUE(run_until(io, [&] { return sink.records.size() >= 1; }));

  bus.unplug(2);
  ASSERT_TRUE(run_until(io, [&] { return said(notes, "reopening it when it comes back"); }));
  bus.replug(2);
  ASSERT_TRUE(run_until(io, [&] { return said(notes, "back after"); }));
  ASSERT_EQ(::write(master, kSecond.data(), kSecond.size()), 8);
  ASSERT_TRUE(run_until(io, [&] { return sink.records.size() >= 2; }));
  capture.stop();
  ::close(master);
  bus.stop();

  ASSERT_EQ(sink.records.size(), 2U);
  EXPECT_EQ(capture.summary().disconnects, 1U);
  EXPECT_EQ(sink.records[0].line_errors, 0);
  // The first frame after the gap says bytes may have been lost before it.
  EXPECT_NE(sink.records[1].line_errors & kOverrun, 0);
  EXPECT_EQ(
      std::vector<std::uint8_t>(sink.records[1].bytes().begin(), sink.records[1].bytes().end()),
      kSecond);

  PcapReader reader(file);
  CapturePacket packet;
  bool lost = false;
  while (reader.next(packet)) {
    std::string error;
    const auto rec = parse_rtac_record(packet.data, error);
    ASSERT_TRUE(rec.has_value()) << error;
    if (rec->event == static_cast<std::uint8_t>(RtacEvent::kCaptureDataLost)) {
      lost = true;
      EXPECT_NE(packet.comment.find(bus.paths()[2]), std::string_view::npos);
    }
  }
  EXPECT_TRUE(lost);
}

// A request nobody answers times out live once the response timeout has passed with the
// line quiet. The recording ends with the stop time, so its replay decides the same.
TEST_F(LiveCaptureTest, RequestTimedOutLiveTimesOutOnReplayToo) {
  VirtualBusOptions bus_options;
  bus_options.line = LineSettings{19200, Parity::kNone, 1};
  VirtualBus bus(bus_options);
  bus.start();
  const std::string file = (dir_ / "timeout.pcapng").string();
  PcapngRecorder recorder(file);
  CollectingSink sink;
  LiveOptions options;
  options.ports = {bus.paths()[2]};
  options.line = bus_options.line;
  options.response_timeout = 100 * kNanosPerMilli;
  boost::asio::io_context io;
  SystemClock clock;
  LiveCapture capture(io, clock, options, sink, &recorder, [](const std::string&) {});
  capture.start();
  const int master = open_bus_endpoint(bus.paths()[0]);
  const std::vector<std::uint8_t> request = with_crc({0x05, 0x03, 0x00, 0x00, 0x00, 0x02});
  ASSERT_EQ(::write(master, request.data(), request.size()), 8);
  ASSERT_TRUE(run_until(io, [&] { return sink.records.size() >= 1; }));
  capture.stop();
  ::close(master);
  bus.stop();
  ASSERT_EQ(sink.records.size(), 1U);
  EXPECT_TRUE(sink.records[0].issues.has(IssueId::kTimeout));

  // The recording declares its response timeout: replay uses it, not the 1 s default.
  ReplayOptions replay_options;
  CollectingSink replayed;
  replay_capture(file, replay_options, replayed);
  ASSERT_EQ(replayed.records.size(), 1U);
  EXPECT_TRUE(replayed.records[0].issues.has(IssueId::kTimeout));
  EXPECT_EQ(replayed.records[0].t_start, sink.records[0].t_start);
}

TEST(Rotation, SizesAndDurationsParse) {
  EXPECT_EQ(parse_rotation("100MB").max_bytes, 100'000'000U);
  EXPECT_EQ(parse_rotation("2gb").max_bytes, 2'000'000'000U);
  EXPECT_EQ(parse_rotation("1h").max_age, 3600 * kNanosPerSecond);
  EXPECT_EQ(parse_rotation("30m").max_age, 1800 * kNanosPerSecond);
  EXPECT_THROW(parse_rotation("soon"), InputError);
  EXPECT_THROW(parse_rotation("10"), InputError);
}

TEST(Rotation, NewFilesStartAtTheLimitAndOnlyTheNewestAreKept) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("rtuscope_rotate_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  RotationPolicy policy = parse_rotation("1s");
  policy.keep = 2;
  {
    PcapngRecorder recorder((dir / "cap.pcapng").string(), policy);
    SerialStatus status;
    status.resolution = kNanosPerMilli;
    recorder.add_port(0, "/dev/ttyX", LineSettings{}, status, kNanosPerSecond);
    const std::vector<std::uint8_t> bytes = {1, 2, 3};
    for (int s = 0; s < 5; ++s) {
      Chunk chunk;
      chunk.t_end = 1'700'000'000 * kNanosPerSecond + s * kNanosPerSecond;
      chunk.bytes = bytes;
      recorder.on_chunk(0, chunk);
    }
    EXPECT_EQ(recorder.files().size(), 5U);
  }
  std::vector<std::string> left;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    left.push_back(e.path().filename().string());
  }
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"cap-0004.pcapng", "cap-0005.pcapng"}));
  PcapReader reader((dir / "cap-0005.pcapng").string());
  CapturePacket packet;
  ASSERT_TRUE(reader.next(packet));  // each file has its own header and interface
  EXPECT_EQ(packet.interface_name, "/dev/ttyX");
  std::filesystem::remove_all(dir);
}

// A recorder started again over the same name (a restart after a power cut) goes on after
// the highest number of the set, where it wrote over cap-0001 before; the set's older files
// count towards `keep`, and files that only look alike are neither counted nor touched.
TEST(Rotation, ARecorderStartedAgainGoesOnAfterTheSetsHighestNumber) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("rtuscope_rotate_again_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const Nanos t0 = 1'700'000'000 * kNanosPerSecond;
  const auto record_seconds = [&](int first, int count, std::size_t keep) {
    RotationPolicy policy = parse_rotation("1s");
    policy.keep = keep;
    PcapngRecorder recorder((dir / "cap.pcapng").string(), policy);
    SerialStatus status;
    status.resolution = kNanosPerMilli;
    recorder.add_port(0, "/dev/ttyX", LineSettings{}, status, kNanosPerSecond);
    const std::vector<std::uint8_t> bytes = {1, 2, 3};
    for (int s = first; s < first + count; ++s) {
      Chunk chunk;
      chunk.t_end = t0 + s * kNanosPerSecond;
      chunk.bytes = bytes;
      recorder.on_chunk(0, chunk);
    }
    return recorder.files();
  };
  for (const char* other : {"cap-12.pcapng", "cap-notes.pcapng", "cap-0009.txt"}) {
    std::ofstream(dir / other) << "not a recording\n";
  }
  EXPECT_EQ(record_seconds(0, 3, 0).back(), (dir / "cap-0003.pcapng").string());
  const std::vector<std::string> again = record_seconds(10, 3, 4);
  EXPECT_EQ(again, (std::vector<std::string>{(dir / "cap-0004.pcapng").string(),
                                             (dir / "cap-0005.pcapng").string(),
                                             (dir / "cap-0006.pcapng").string()}));
  std::vector<std::string> left;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    left.push_back(e.path().filename().string());
  }
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"cap-0003.pcapng", "cap-0004.pcapng", "cap-0005.pcapng",
                                            "cap-0006.pcapng", "cap-0009.txt", "cap-12.pcapng",
                                            "cap-notes.pcapng"}));
  // The first run's last file is as it wrote it: its read at second 2.
  PcapReader reader((dir / "cap-0003.pcapng").string());
  CapturePacket packet;
  ASSERT_TRUE(reader.next(packet));
  EXPECT_EQ(packet.t, t0 + 2 * kNanosPerSecond);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rtu
