// The hand-made sample capture captures/device_examples.hex (written by
// tools/make_examples_capture.py) must stay what its header promises: every documented
// example frame of the four devices, CRC-correct except the one bad-CRC request kept on
// purpose, on a 9600 8E1 bus, one byte per line; and its two Saleae versions the same bytes.
#include <gtest/gtest.h>

#include <vector>

#include "capture/chunk_view.hpp"
#include "capture/open_capture.hpp"
#include "capture/text_hex_reader.hpp"
#include "core/crc16.hpp"

namespace rtu {
namespace {

TEST(DeviceExamplesCapture, HoldsEveryExampleFrameWithOneDeliberateBadCrc) {
  const std::string path = std::string(RTUSCOPE_SOURCE_DIR) + "/captures/device_examples.hex";
  auto source = open_capture(path);
  ASSERT_NE(dynamic_cast<TextHexReader*>(source.get()), nullptr);
  const auto settings = source->declared_settings();
  ASSERT_TRUE(settings.has_value());
  EXPECT_EQ(settings->describe(), "9600 8E1");

  // Split on silences: bytes of a frame are one character time apart, frames ≥ 5 ms apart.
  std::vector<std::vector<std::uint8_t>> frames;
  ChunkView chunks(*source);
  Chunk chunk;
  Nanos last = kUnknownTime;
  while (chunks.next(chunk)) {
    ASSERT_EQ(chunk.bytes.size(), 1U) << "one byte per line, line " << chunk.origin;
    if (last == kUnknownTime || chunk.t_end - last > settings->t3_5()) frames.emplace_back();
    if (last != kUnknownTime) {
      EXPECT_GE(chunk.t_end - last, settings->char_time());
    }
    frames.back().push_back(chunk.bytes[0]);
    last = chunk.t_end;
  }
  // 29 documented requests, 28 responses (one TH900 example has none).
  EXPECT_EQ(frames.size(), 57U);
  std::vector<std::vector<std::uint8_t>> bad;
  for (const auto& f : frames) {
    if (!crc16_valid(f)) bad.push_back(f);
  }
  const std::vector<std::uint8_t> yakotec_bad_crc = {0x01, 0x03, 0x00, 0x20,
                                                     0x00, 0x01, 0x85, 0xC1};
  ASSERT_EQ(bad.size(), 1U);
  EXPECT_EQ(bad[0], yakotec_bad_crc);
  EXPECT_EQ(source->timestamp_precision(), 1);
}

}  // namespace
}  // namespace rtu

namespace rtu {
namespace {

struct TimedByte {
  Nanos start;
  Nanos end;
  std::uint8_t value;
};

std::vector<TimedByte> bytes_of(const std::string& file) {
  auto source = open_capture(std::string(RTUSCOPE_SOURCE_DIR) + "/captures/" + file);
  std::vector<TimedByte> out;
  ChunkView chunks(*source);
  Chunk chunk;
  while (chunks.next(chunk)) {
    EXPECT_EQ(chunk.bytes.size(), 1U);
    out.push_back({chunk.t_first_start, chunk.t_end, chunk.bytes[0]});
  }
  return out;
}

TEST(DeviceExamplesCapture, SaleaeVersionsCarryTheSameBytesAtTheSameRelativeTimes) {
  const Nanos char_time = LineSettings{}.char_time();
  const auto hex = bytes_of("device_examples.hex");
  const auto legacy = bytes_of("device_examples_saleae_legacy.csv");
  const auto table = bytes_of("device_examples_saleae_table.csv");
  ASSERT_FALSE(hex.empty());
  ASSERT_EQ(legacy.size(), hex.size());
  ASSERT_EQ(table.size(), hex.size());
  // Legacy times count from a trigger on the first start bit; the table's from 1 ms before.
  const Nanos first_start = hex[0].end - char_time;
  for (std::size_t i = 0; i < hex.size(); ++i) {
    EXPECT_EQ(legacy[i].value, hex[i].value);
    EXPECT_EQ(table[i].value, hex[i].value);
    EXPECT_EQ(legacy[i].start, hex[i].end - char_time - first_start) << i;
    EXPECT_EQ(legacy[i].end, legacy[i].start) << "the legacy layout has no duration";
    EXPECT_EQ(table[i].start, legacy[i].start + kNanosPerMilli) << i;
    EXPECT_EQ(table[i].end, table[i].start + char_time) << i;
  }
}

}  // namespace
}  // namespace rtu
