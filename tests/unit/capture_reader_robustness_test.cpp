// Damaged capture files, generated from a fixed seed: a reader either reads them (and then
// keeps its promises: non-empty chunks, one error flag per byte when any, times that never go
// backwards, origins that grow) or throws InputError. Anything else (another exception, a
// sanitizer report) fails.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "capture/chunk_view.hpp"
#include "capture/open_capture.hpp"
#include "capture_test_files.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

using testing::TempDir;

const std::vector<std::string>& seeds() {
  static const std::vector<std::string> kSeeds = {
      "# baud=9600 parity=E stop=1\n0.001 01 03 00 00\n0.002 0002C40B\n-1.5 ff\n",
      "Time [s],Value,Parity Error,Framing Error\n0.000001,0x01,,\n0.002,0x03,Error,Error\n",
      "name,type,start_time,duration,\"data\",\"error\"\n\"Async 1\",\"data\",0.000592672,"
      "8.2464e-05,0x31,\n\"A\",data,2022-06-29T04:05:27.591152100+00:00,1e-3,0xFF,parity\n",
  };
  return kSeeds;
}

std::string mutate(std::mt19937& rng, std::string text) {
  static constexpr std::string_view kAlphabet = "0123456789abcdefxX.,-+eE:T \t\"#=\r\n\x00\xff";
  const int edits = 1 + static_cast<int>(rng() % 6);
  for (int e = 0; e < edits; ++e) {
    const std::size_t pos = text.empty() ? 0 : rng() % text.size();
    const char c = kAlphabet[rng() % kAlphabet.size()];
    switch (rng() % 4) {
      case 0:
        if (!text.empty()) text[pos] = c;
        break;
      case 1: text.insert(pos, 1, c); break;
      case 2:
        if (!text.empty()) text.erase(pos, 1 + rng() % 8);
        break;
      default: text.insert(pos, text.substr(rng() % (text.size() + 1), rng() % 40)); break;
    }
  }
  return text;
}

TEST(CaptureReaderRobustness, DamagedFilesAreReadOrRefusedWithInputError) {
  TempDir dir;
  std::mt19937 rng(20250101);
  int read_ok = 0;
  int refused = 0;
  for (int round = 0; round < 600; ++round) {
    const std::string& seed = seeds()[static_cast<std::size_t>(round) % seeds().size()];
    const auto path = dir.write(round % 2 == 0 ? "f.csv" : "f.hex", mutate(rng, seed));
    try {
      auto reader = open_capture(path, [](std::string_view) {});
      ChunkView source(*reader);
      Chunk chunk;
      Nanos last_time = kUnknownTime;
      std::uint64_t last_origin = 0;
      while (source.next(chunk)) {
        ASSERT_FALSE(chunk.bytes.empty()) << path;
        ASSERT_TRUE(chunk.errors.empty() || chunk.errors.size() == chunk.bytes.size());
        const Nanos t = chunk.t_first_start != kUnknownTime ? chunk.t_first_start : chunk.t_end;
        ASSERT_NE(t, kUnknownTime);
        if (last_time != kUnknownTime) {
          ASSERT_GE(t, last_time) << "time went backwards";
        }
        ASSERT_GE(chunk.t_end,
                  chunk.t_first_start == kUnknownTime ? chunk.t_end : chunk.t_first_start);
        ASSERT_GT(chunk.origin, last_origin);
        last_time = t;
        last_origin = chunk.origin;
      }
      ++read_ok;
    } catch (const InputError& e) {
      // The message must say where: it starts with the path.
      ASSERT_EQ(std::string(e.what()).rfind(path + ":", 0), 0U) << e.what();
      ++refused;
    }
  }
  // Both outcomes must really occur, or the mutations test nothing.
  EXPECT_GT(read_ok, 30) << refused;
  EXPECT_GT(refused, 50) << read_ok;
}

}  // namespace
}  // namespace rtu
