// Progress of the replay driver (ReplayOptions::on_progress): input bytes consumed per pass,
// as the text hex and pcapng readers count them, up to the file's size.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "capture/byte_output.hpp"
#include "capture_test_files.hpp"
#include "core/input_error.hpp"
#include "pipeline/replay.hpp"
#include "report/pcap_export.hpp"

namespace rtu {
namespace {

using test::CollectingSink;
using Pass = ReplayProgress::Pass;

// Enough lines for several reports per pass between the final ones.
constexpr int kLines = 3 * static_cast<int>(kProgressEvery) + 100;

// A request and its answer, one read each, kLines lines in all.
std::string text_capture() {
  std::string text = "# baud=9600 parity=E stop=1\n";
  for (int i = 0; i < kLines; ++i) {
    const bool request = i % 2 == 0;
    const int ms = i * 10;  // answers 10 ms after their request
    text += fmt::format("{}.{:03} ", 1'700'000'000 + ms / 1000, ms % 1000);
    text += request ? "01 03 00 00 00 01 84 0A\n" : "01 03 02 12 34 B5 33\n";
  }
  return text;
}

struct Seen {
  std::vector<ReplayProgress> calls;
  void check_pass(Pass pass, std::uint64_t size, bool complete) const {
    std::uint64_t last = 0;
    int middle = 0;
    const ReplayProgress* final_call = nullptr;
    for (const auto& c : calls) {
      if (c.pass != pass) continue;
      EXPECT_EQ(c.input_size, size);
      EXPECT_GE(c.bytes_read, last) << "progress went back";
      EXPECT_LE(c.bytes_read, size);
      last = c.bytes_read;
      if (!c.pass_done && c.bytes_read > 0 && c.bytes_read < size) ++middle;
      final_call = &c;
    }
    ASSERT_NE(final_call, nullptr);
    EXPECT_TRUE(final_call->pass_done);
    EXPECT_GE(middle, 1) << "no report between the start and the end";
    if (complete) {
      EXPECT_EQ(final_call->bytes_read, size);
    }
  }
};

TEST(ReplayProgress, TextHexPassesCountBytesUpToTheFileSize) {
  testing::TempDir temp;
  const std::string path = temp.write("bus.hex", text_capture());
  const auto size = std::filesystem::file_size(path);
  Seen seen;
  ReplayOptions options;
  options.show_warnings = false;
  options.on_progress = [&](const ReplayProgress& p) { seen.calls.push_back(p); };
  CollectingSink sink;
  replay_capture(path, options, sink);
  ASSERT_FALSE(seen.calls.empty());
  EXPECT_EQ(seen.calls.front().pass, Pass::kSurvey);
  EXPECT_EQ(seen.calls.back().pass, Pass::kDecode);
  seen.check_pass(Pass::kSurvey, size, true);
  seen.check_pass(Pass::kDecode, size, true);
  // One record per data line; a report every kProgressEvery records.
  EXPECT_EQ(seen.calls.back().records, static_cast<std::uint64_t>(kLines));
  EXPECT_EQ(seen.calls.size(), 2 * (kLines / kProgressEvery + 1));
}

TEST(ReplayProgress, PcapngPassesCountBytesUpToTheFileSize) {
  testing::TempDir temp;
  const std::string text = temp.write("bus.hex", text_capture());
  const std::string pcapng = (temp.path() / "bus.pcapng").string();
  {
    PcapExportSink exporter(std::make_unique<FileOutput>(pcapng), PcapExportOptions{});
    ReplayOptions options;
    options.show_warnings = false;
    replay_capture(text, options, exporter);
  }
  Seen seen;
  ReplayOptions options;
  options.show_warnings = false;
  options.on_progress = [&](const ReplayProgress& p) { seen.calls.push_back(p); };
  CollectingSink sink;
  replay_capture(pcapng, options, sink);
  const auto size = std::filesystem::file_size(pcapng);
  seen.check_pass(Pass::kSurvey, size, true);
  seen.check_pass(Pass::kDecode, size, true);
}

TEST(ReplayProgress, DamagedInputEndsEachPassWhereItStopped) {
  testing::TempDir temp;
  const std::string path = temp.write("bus.hex", text_capture() + "not a capture line\n");
  const auto size = std::filesystem::file_size(path);
  Seen seen;
  ReplayOptions options;
  options.show_warnings = false;
  options.on_progress = [&](const ReplayProgress& p) { seen.calls.push_back(p); };
  CollectingSink sink;
  EXPECT_THROW(replay_capture(path, options, sink), InputError);
  seen.check_pass(Pass::kSurvey, size, false);
  seen.check_pass(Pass::kDecode, size, false);
  // The error still ends the decoding pass, so a display can finish its line.
  ASSERT_FALSE(seen.calls.empty());
  EXPECT_TRUE(seen.calls.back().pass_done);
  EXPECT_EQ(seen.calls.back().pass, Pass::kDecode);
}

}  // namespace
}  // namespace rtu
