// pcap and pcapng records whose times go backwards (another tool's clock stepped, two threads
// stamped them) are kept in file order, clamped to the time before, and reported with the
// file and offset, as text captures report theirs by line. Without the clamp, frame records
// left out of order with negative latencies.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "capture/byte_output.hpp"
#include "capture/open_capture.hpp"
#include "capture/pcap_format.hpp"
#include "capture/pcapng_writer.hpp"
#include "capture/rtac_serial.hpp"
#include "capture/upper_pdu.hpp"
#include "capture_test_files.hpp"
#include "pipeline/replay.hpp"

namespace rtu {
namespace {

using test::CollectingSink;
using testing::TempDir;
using Bytes = std::vector<std::uint8_t>;

constexpr Nanos kStart = 1'700'000'000 * kNanosPerSecond;
constexpr Nanos kMs = kNanosPerMilli;
const Bytes kRequest = {0x01, 0x03, 0x00, 0x32, 0x00, 0x03, 0xA4, 0x04};
const Bytes kResponse = {0x01, 0x03, 0x06, 0xEA, 0x60, 0xC3, 0x50, 0xDB, 0x6C, 0xD1, 0x3F};

struct Timed {
  Nanos t;
  Bytes bytes;
};

std::string capture_of(const TempDir& dir, std::uint16_t link_type,
                       const std::vector<Timed>& items) {
  const auto path = (dir.path() / "backwards.pcapng").string();
  PcapngWriter w(std::make_unique<FileOutput>(path));
  const auto id = w.add_interface({link_type, "", "RS-485 9600 8E1", 9, 0});
  Bytes record;
  for (const auto& item : items) {
    if (link_type == pcap::kLinkTypeUpperPdu) {
      build_upper_pdu(item.bytes, {upper_pdu::kModbusRtuDissector, PduDirection::kUnknown, ""},
                      record);
    } else {
      build_rtac_record(item.t, RtacEvent::kDataRxStart, 0, item.bytes, record);
    }
    w.write_packet(id, item.t, record);
  }
  return path;
}

std::vector<std::string> warnings_of(const std::string& path) {
  std::vector<std::string> warnings;
  auto reader = open_capture(path, [&](std::string_view w) { warnings.emplace_back(w); });
  testing::read_all(*reader);
  return warnings;
}

std::vector<Record> decode(const std::string& path) {
  CollectingSink sink;
  ReplayOptions options;
  options.show_warnings = false;
  replay_capture(path, options, sink);
  return sink.records;
}

TEST(PcapBackwardTime, FrameRecordsAreClampedAndReported) {
  TempDir dir;
  // The response's record is stamped 400 ms before its request's.
  const auto path =
      capture_of(dir, pcap::kLinkTypeUpperPdu,
                 {{kStart + 10'000 * kMs, kRequest}, {kStart + 9'600 * kMs, kResponse}});
  const auto warnings = warnings_of(path);
  ASSERT_EQ(warnings.size(), 1U);
  EXPECT_NE(warnings[0].find(path + ": offset "), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("goes backwards (1700000009.600000000 s after 1700000010.000000000 s"),
            std::string::npos)
      << warnings[0];

  const auto records = decode(path);
  ASSERT_EQ(records.size(), 2U);
  EXPECT_LE(records[0].t_start, records[1].t_start);
  EXPECT_EQ(records[1].t_start, records[0].t_end) << "starts when the line is free";
  EXPECT_TRUE(records[1].latency == kUnknownTime || records[1].latency >= 0)
      << "latency " << records[1].latency;
}

TEST(PcapBackwardTime, RawReadsAreClampedAndReported) {
  TempDir dir;
  const auto path = capture_of(dir, pcap::kLinkTypeRtacSerial,
                               {{kStart + 10'000 * kMs, kRequest},
                                {kStart + 9'000 * kMs, kResponse},
                                {kStart + 11'000 * kMs, kRequest}});
  const auto warnings = warnings_of(path);
  ASSERT_EQ(warnings.size(), 1U);
  EXPECT_NE(warnings[0].find("goes backwards"), std::string::npos) << warnings[0];
  auto reader = open_capture(path, {});
  const auto chunks = testing::read_all(*reader);
  ASSERT_EQ(chunks.size(), 3U);
  EXPECT_EQ(chunks[1].t_end, kStart + 10'000 * kMs) << "clamped to the read before";
  EXPECT_EQ(chunks[2].t_end, kStart + 11'000 * kMs);
  EXPECT_FALSE(chunks[0].time_clamped);
  EXPECT_TRUE(chunks[1].time_clamped);
  EXPECT_FALSE(chunks[2].time_clamped);
}

TEST(PcapBackwardTime, ManyAreCountedAfterTheFirstFew) {
  TempDir dir;
  std::vector<Timed> items;
  for (int i = 0; i < 20; ++i) items.push_back({kStart + (i % 2 == 0 ? 1000 : 0) * kMs, kRequest});
  const auto warnings = warnings_of(capture_of(dir, pcap::kLinkTypeUpperPdu, items));
  ASSERT_EQ(warnings.size(), static_cast<std::size_t>(BackwardTimeClamp::kDetailed) + 1);
  EXPECT_NE(warnings.back().find("5 more timestamps went backwards and were clamped (10 in all)"),
            std::string::npos)
      << warnings.back();
}

}  // namespace
}  // namespace rtu
