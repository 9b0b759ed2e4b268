// Several capture files read as one capture (capture/capture_set_reader.hpp): a recording
// rotated into files by the live recorder decodes exactly as the same recording in one file,
// whatever order the files are named in; a missing file is reported; files that overlap in
// time or declare other line settings are errors naming both.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "bus_builder.hpp"
#include "capture/capture_paths.hpp"
#include "capture/capture_set_gaps.hpp"
#include "capture/capture_set_reader.hpp"
#include "capture/pcap_capture_reader.hpp"
#include "capture/pcap_reader.hpp"
#include "capture_test_files.hpp"
#include "core/input_error.hpp"
#include "pipeline/pcapng_recorder.hpp"
#include "pipeline/replay.hpp"

namespace rtu {
namespace {

using test::BusBuilder;
using test::CollectingSink;
using test::with_crc;
using testing::TempDir;

constexpr Nanos kMs = kNanosPerMilli;
// Recordings are stamped on the wall clock, as live ones are.
constexpr Nanos kWallClock = 1'700'000'000 * kNanosPerSecond;

// 80 polls about 100 ms apart, read by a USB adapter: some answered late, one never, one
// answer damaged, one turnaround glitch; the kind of traffic whose pairing and timing must
// survive a file boundary.
std::vector<Chunk> traffic(BusBuilder& bus, std::vector<std::vector<std::uint8_t>>& keep) {
  for (int i = 0; i < 80; ++i) {
    const auto slave = static_cast<std::uint8_t>(1 + i % 3);
    bus.add(with_crc({slave, 0x03, 0x00, static_cast<std::uint8_t>(i), 0x00, 0x01}), 80 * kMs);
    if (i % 13 == 7) continue;  // no answer
    auto response = with_crc({slave, 0x03, 0x02, 0x12, static_cast<std::uint8_t>(i)});
    if (i % 17 == 5) response[3] ^= 0x40U;  // damaged on the line
    bus.add(response, (i % 11 == 3 ? 30 : 4) * kMs);
    if (i % 19 == 2) bus.add({0xFE}, kMs / 10);
  }
  auto chunks = bus.usb(2 * kMs, 32);
  // The chunks' spans point into the builder; keep copies so they outlive it.
  for (auto& chunk : chunks) {
    keep.emplace_back(chunk.bytes.begin(), chunk.bytes.end());
    chunk.bytes = keep.back();
    chunk.t_end += kWallClock;
  }
  return chunks;
}

// Records `chunks` as `rtuscope live -w path` would, stopped 0.5 s after the last read (or
// cut off right after it, without `stopped`); returns the files written.
std::vector<std::string> record(const std::string& path, const std::vector<Chunk>& chunks,
                                RotationPolicy rotation = {}, LineSettings line = {},
                                bool stopped = true) {
  PcapngRecorder recorder(path, rotation);
  SerialStatus status;
  status.resolution = 2 * kMs;
  recorder.add_port(0, "/dev/ttyUSB0", line, status, 50 * kMs);
  for (const auto& chunk : chunks) recorder.on_chunk(0, chunk);
  if (stopped && !chunks.empty()) recorder.on_end(chunks.back().t_end + 500 * kMs);
  recorder.flush();
  return recorder.files();
}

struct Decoded {
  CaptureInfo info;
  CollectingSink sink;
};

void decode(const std::vector<std::string>& paths, Decoded& out) {
  ReplayOptions options;
  options.show_warnings = false;
  out.info = replay_capture(paths, options, out.sink);
}

// Every field of a record but its origin (an offset in its own file, so necessarily
// different) and the pointers valid only while it was delivered.
std::string describe(const Record& r) {
  std::string s = fmt::format("{} seq={} t={} end={} gap={} bytes=", static_cast<int>(r.kind),
                              r.seq, r.t_start, r.t_end, r.gap_before);
  for (const auto b : r.bytes()) s += fmt::format("{:02x}", b);
  s += fmt::format(" errors={} fit={} crc={} issues={:x} role={} txn={} latency={}", r.line_errors,
                   r.shape_fit, r.crc_ok, r.issues.bits(), static_cast<int>(r.role), r.txn,
                   r.latency);
  return s;
}

std::vector<std::string> describe_all(const std::vector<Record>& records) {
  std::vector<std::string> out;
  for (const auto& r : records) out.push_back(describe(r));
  return out;
}

Nanos first_time(const std::string& path) {
  PcapReader reader(path);
  CapturePacket packet;
  EXPECT_TRUE(reader.next(packet)) << path;
  return packet.t;
}

// The whole recording in one file, and the same recording rotated by age, the age chosen so
// that the first boundary falls between a request (the first file's last read) and its
// response (the second file's first read), about a second into the recording.
struct Recording {
  TempDir dir;
  BusBuilder bus;
  std::vector<std::vector<std::uint8_t>> bytes;
  std::vector<Chunk> chunks;
  std::size_t response = 0;  // the second file's first chunk
  std::string whole;
  std::vector<std::string> parts;

  Recording() {
    chunks = traffic(bus, bytes);
    whole = record((dir.path() / "whole.pcapng").string(), chunks).front();
    // A response starts a few ms after its request; the next request 80 ms after that.
    for (response = 1; response < chunks.size(); ++response) {
      const Nanos since = chunks[response].t_end - chunks[response - 1].t_end;
      if (chunks[response].t_end - chunks.front().t_end >= kNanosPerSecond && since > 3 * kMs &&
          since < 20 * kMs) {
        break;
      }
    }
    RotationPolicy rotation;
    rotation.max_age = chunks[response].t_end - chunks.front().t_end;
    parts = record((dir.path() / "site.pcapng").string(), chunks, rotation);
  }
};

void expect_same_capture(const Decoded& set, const Decoded& whole) {
  EXPECT_EQ(describe_all(set.sink.records), describe_all(whole.sink.records));
  EXPECT_EQ(describe_all(set.sink.requests_of_responses),
            describe_all(whole.sink.requests_of_responses));
  EXPECT_TRUE(set.sink.finished);
  EXPECT_EQ(set.info.line.describe(), whole.info.line.describe());
  EXPECT_EQ(set.info.timing_resolution, whole.info.timing_resolution);
  EXPECT_EQ(set.info.per_byte_timing, whole.info.per_byte_timing);
  EXPECT_EQ(set.info.response_timeout, whole.info.response_timeout);
  EXPECT_EQ(set.info.warnings, whole.info.warnings);
}

TEST(CaptureSet, RotatedFilesDecodeExactlyAsTheWholeRecording) {
  Recording rec;
  ASSERT_GE(rec.parts.size(), 4U);
  EXPECT_EQ(std::filesystem::path(rec.parts[0]).filename(), "site-0001.pcapng");
  Decoded whole;
  decode({rec.whole}, whole);
  Decoded set;
  decode(rec.parts, set);
  ASSERT_GT(whole.sink.records.size(), 60U);
  expect_same_capture(set, whole);
  EXPECT_TRUE(set.info.warnings.empty());  // nothing missing
  EXPECT_EQ(set.info.source, fmt::format("{} \u2026 {} ({} files)", rec.parts.front(),
                                         rec.parts.back(), rec.parts.size()));

  // The transaction whose request is in the first file and whose response is in the second.
  ASSERT_LT(rec.response, rec.chunks.size());
  const Nanos second_starts = rec.chunks[rec.response].t_end;
  EXPECT_EQ(first_time(rec.parts[1]), second_starts);
  const Nanos first_ends = rec.chunks[rec.response - 1].t_end;
  const auto split =
      std::find_if(set.sink.records.begin(), set.sink.records.end(), [&](const Record& r) {
        return r.role == Role::kResponse && r.t_start > first_ends && r.t_start <= second_starts;
      });
  ASSERT_NE(split, set.sink.records.end());
  EXPECT_GE(split->txn, 0);  // paired across the boundary
  EXPECT_TRUE(split->crc_ok);
  ASSERT_NE(split->latency, kUnknownTime);  // and timed across it
  EXPECT_LE(split->t_start - split->latency, first_ends);
}

TEST(CaptureSet, FilesAreReadInTimeOrderWhateverTheirNamesOrOrder) {
  Recording rec;
  ASSERT_GE(rec.parts.size(), 4U);
  // Names whose order is not the time order, given in yet another order.
  std::vector<std::string> renamed;
  for (std::size_t i = 0; i < rec.parts.size(); ++i) {
    // "z-0.pcapng", "y-1.pcapng", ...: the name order is the reverse of the time order.
    const auto to =
        (rec.dir.path() / fmt::format("{}-{}.pcapng", static_cast<char>('z' - i), i)).string();
    std::filesystem::rename(rec.parts[i], to);
    renamed.push_back(to);
  }
  std::vector<std::string> given = renamed;
  std::reverse(given.begin(), given.end());
  std::swap(given[0], given[2]);

  CaptureSetReader reader({given.begin(), given.end()}, [](std::string_view) {});
  EXPECT_EQ(reader.paths(), renamed);

  Decoded whole;
  decode({rec.whole}, whole);
  Decoded set;
  decode(given, set);
  expect_same_capture(set, whole);
}

TEST(CaptureSet, AMissingMiddleFileIsReportedByItsNumber) {
  Recording rec;
  ASSERT_GE(rec.parts.size(), 4U);
  std::vector<std::string> left = rec.parts;
  left.erase(left.begin() + 1);
  Decoded set;
  decode(left, set);
  ASSERT_EQ(set.info.warnings.size(), 1U);
  const std::string& warning = set.info.warnings[0];
  EXPECT_NE(warning.find(rec.parts[2] + ": a file seems to be missing before it (after " +
                         rec.parts[0] + ")"),
            std::string::npos)
      << warning;
  EXPECT_NE(warning.find("the rotation numbering skips " + rec.parts[1]), std::string::npos)
      << warning;
}

TEST(CaptureSet, AMissingFileIsReportedByTheSilenceWhereNamesSayNothing) {
  TempDir dir;
  BusBuilder bus;
  std::vector<std::vector<std::uint8_t>> bytes;
  const auto chunks = traffic(bus, bytes);
  RotationPolicy rotation;
  rotation.max_age = 2500 * kMs;
  const auto parts = record((dir.path() / "line.pcapng").string(), chunks, rotation);
  ASSERT_GE(parts.size(), 3U);
  const auto first = (dir.path() / "monday.pcapng").string();
  const auto third = (dir.path() / "wednesday.pcapng").string();
  std::filesystem::rename(parts[0], first);
  std::filesystem::rename(parts[2], third);

  Decoded set;
  decode({third, first}, set);
  ASSERT_EQ(set.info.warnings.size(), 1U);
  const std::string& warning = set.info.warnings[0];
  EXPECT_NE(warning.find(third + ": a file seems to be missing before it (after " + first + ")"),
            std::string::npos)
      << warning;
  EXPECT_NE(warning.find("no record for 2."), std::string::npos) << warning;
  EXPECT_EQ(warning.find("numbering"), std::string::npos) << warning;

  // The whole set has no such silence.
  Decoded all;
  std::vector<std::string> every = parts;
  every[0] = first;
  every[2] = third;
  decode(every, all);
  EXPECT_TRUE(all.info.warnings.empty());
}

TEST(CaptureSet, FilesThatOverlapInTimeAreAnErrorNamingBoth) {
  TempDir dir;
  BusBuilder bus;
  std::vector<std::vector<std::uint8_t>> bytes;
  const auto chunks = traffic(bus, bytes);
  const std::size_t half = chunks.size() / 2;
  const auto early = record((dir.path() / "early.pcapng").string(),
                            {chunks.begin(), chunks.begin() + static_cast<long>(half + 10)})
                         .front();
  const auto late = record((dir.path() / "late.pcapng").string(),
                           {chunks.begin() + static_cast<long>(half), chunks.end()})
                        .front();
  Decoded set;
  try {
    decode({late, early}, set);
    FAIL() << "overlapping files were read as one capture";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(late + ": its first record"), std::string::npos) << what;
    EXPECT_NE(what.find("last record of " + early), std::string::npos) << what;
    EXPECT_NE(what.find("overlap in time"), std::string::npos) << what;
  }
  // Everything before the error was delivered: the whole earlier file.
  Decoded alone;
  decode({early}, alone);
  EXPECT_EQ(describe_all(set.sink.records), describe_all(alone.sink.records));
}

TEST(CaptureSet, FilesOfOtherLineSettingsAreAnErrorNamingBoth) {
  TempDir dir;
  BusBuilder bus;
  std::vector<std::vector<std::uint8_t>> bytes;
  const auto chunks = traffic(bus, bytes);
  const auto half = static_cast<long>(chunks.size() / 2);
  const auto first = record((dir.path() / "first.pcapng").string(),
                            {chunks.begin(), chunks.begin() + half}, {}, {}, false)
                         .front();
  LineSettings other;
  other.baud = 19200;
  other.parity = Parity::kNone;
  const auto second = record((dir.path() / "second.pcapng").string(),
                             {chunks.begin() + half, chunks.end()}, {}, other)
                          .front();
  Decoded set;
  try {
    decode({first, second}, set);
    FAIL() << "files of two lines were read as one capture";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(
        what.find(second + ": declares the line 19200 8N1, but " + first + " declares 9600 8E1"),
        std::string::npos)
        << what;
  }
  EXPECT_FALSE(set.sink.records.empty());  // the first file was delivered
}

TEST(CaptureSet, RotationNeverSplitsARead) {
  // Reads with line errors are written as several records of one time; a lost-data event
  // flags the next byte read. With a size limit that every record exceeds, each read (and an
  // event with the read after it) must still land whole in one file.
  TempDir dir;
  const std::vector<std::uint8_t> bytes = {0x01, 0x03, 0x02, 0x00, 0x07};
  const std::vector<std::uint8_t> errors = {0, kParityError, kParityError, 0, kFramingError};
  std::vector<Chunk> chunks;
  for (int i = 0; i < 3; ++i) {
    Chunk chunk;
    chunk.t_end = kWallClock + i * 100 * kMs;
    chunk.bytes = bytes;
    chunk.errors = errors;
    chunks.push_back(chunk);
  }
  RotationPolicy rotation;
  rotation.max_bytes = 1;
  std::vector<std::string> parts;
  {
    PcapngRecorder recorder((dir.path() / "cut.pcapng").string(), rotation);
    recorder.add_port(0, "/dev/ttyUSB0", LineSettings{}, SerialStatus{}, 50 * kMs);
    recorder.on_chunk(0, chunks[0]);
    recorder.on_gap(0, chunks[0].t_end + kMs, "port lost");
    recorder.on_chunk(0, chunks[1]);
    recorder.on_chunk(0, chunks[2]);
    recorder.flush();
    parts = recorder.files();
  }
  ASSERT_EQ(parts.size(), 3U);  // the event went with the read after it, not alone
  for (const auto& part : parts) {
    PcapCaptureReader reader(part, {});
    struct Count final : CaptureConsumer {
      void on_chunk(const Chunk& chunk) override {
        ++chunks;
        size = chunk.bytes.size();
      }
      void on_frame(std::span<const std::uint8_t>, Nanos, std::uint64_t) override {}
      void on_noise(std::span<const std::uint8_t>, Nanos, std::uint64_t) override {}
      void on_end(Nanos) override {}
      int chunks = 0;
      std::size_t size = 0;
    } count;
    while (reader.read(count)) {
    }
    EXPECT_EQ(count.chunks, 1) << part;
    EXPECT_EQ(count.size, bytes.size()) << part;
  }
}

TEST(CaptureSet, MissingFileRules) {
  SetBoundary b;
  b.before = "logs/site-0007.pcapng";
  b.after = "logs/site-0008.pcapng";
  b.silence = 5 * kNanosPerSecond;
  b.longest_within = kNanosPerSecond;
  EXPECT_FALSE(missing_file_warning(b));  // consecutive, and 5 s < 10 × 1 s
  b.after = "logs/site-0011.pcapng";
  EXPECT_EQ(missing_file_warning(b).value_or(""),
            "logs/site-0011.pcapng: a file seems to be missing before it (after "
            "logs/site-0007.pcapng): the rotation numbering skips logs/site-0008.pcapng to "
            "logs/site-0010.pcapng (3 files)");
  b.after = "logs/other-0009.pcapng";  // another recording's numbering says nothing
  EXPECT_FALSE(missing_file_warning(b));
  b.silence = 10 * kNanosPerSecond + 1;
  EXPECT_EQ(missing_file_warning(b).value_or(""),
            "logs/other-0009.pcapng: a file seems to be missing before it (after "
            "logs/site-0007.pcapng): no record for 10.000 s between them, over 10 times the "
            "longest silence within either file (1.000 s)");
  b.longest_within = 0;  // one record per file: short pauses are still not missing files
  b.silence = kNanosPerSecond;
  EXPECT_FALSE(missing_file_warning(b));
  const auto name = parse_rotation_name("a/b-c-0042.pcap");
  ASSERT_TRUE(name);
  EXPECT_EQ(name->stem, "a/b-c");
  EXPECT_EQ(name->number, 42U);
  EXPECT_FALSE(parse_rotation_name("site.pcapng"));
  EXPECT_FALSE(parse_rotation_name("site-x1.pcapng"));
}

// Every field of `describe` but the numbering (a sequence number and a transaction number
// count from 0 in each decoding).
std::string describe_unnumbered(const Record& r) {
  return fmt::format(
      "{} t={} end={} gap={} bytes={:02x} errors={} fit={} crc={} issues={:x} "
      "role={} paired={} latency={}",
      static_cast<int>(r.kind), r.t_start, r.t_end, r.gap_before, fmt::join(r.bytes(), ""),
      r.line_errors, r.shape_fit, r.crc_ok, r.issues.bits(), static_cast<int>(r.role), r.txn >= 0,
      r.latency);
}

// A recorder stopped while a request waited (its end record written), then started again
// over the same name: the set decodes as the two runs' recordings each decoded alone, one
// after the other. The answer that waited in the port for the second run pairs with nothing
// of the first (it was flagged a late answer of the first run's request before), and the
// warning says the recording stopped rather than that a file is missing.
TEST(CaptureSet, ARecorderStartedAgainBreaksTheCaptureAtItsEnd) {
  TempDir dir;
  RotationPolicy rotation;
  rotation.max_age = 3600 * kNanosPerSecond;
  std::vector<std::vector<std::uint8_t>> keep;
  const auto run = [&](Nanos start, bool answer_first, int polls) {
    BusBuilder bus;
    if (answer_first) bus.add(with_crc({1, 0x03, 0x02, 0x00, 0x07}), 0);
    for (int i = 0; i < polls; ++i) {
      bus.add(with_crc({1, 0x03, 0x00, static_cast<std::uint8_t>(i), 0x00, 0x01}), 90 * kMs);
      if (i + 1 < polls || answer_first) bus.add(with_crc({1, 0x03, 0x02, 0x00, 0x01}), 4 * kMs);
    }
    std::vector<Chunk> chunks = bus.per_add();
    for (auto& chunk : chunks) {
      keep.emplace_back(chunk.bytes.begin(), chunk.bytes.end());
      chunk.bytes = keep.back();
      chunk.t_end += start;
    }
    return record((dir.path() / "rec.pcapng").string(), chunks, rotation);
  };
  // The first run's last request is unanswered when it stops (0.5 s after it, see record()).
  const std::vector<std::string> first = run(kWallClock, false, 5);
  const std::vector<std::string> second = run(kWallClock + 2 * kNanosPerSecond, true, 5);
  ASSERT_EQ(first, std::vector<std::string>{(dir.path() / "rec-0001.pcapng").string()});
  ASSERT_EQ(second, std::vector<std::string>{(dir.path() / "rec-0002.pcapng").string()});

  Decoded set;
  decode({first[0], second[0]}, set);
  Decoded alone_first;
  decode(first, alone_first);
  Decoded alone_second;
  decode(second, alone_second);
  std::vector<std::string> expected;
  for (const auto& r : alone_first.sink.records) expected.push_back(describe_unnumbered(r));
  for (const auto& r : alone_second.sink.records) expected.push_back(describe_unnumbered(r));
  std::vector<std::string> got;
  for (const auto& r : set.sink.records) got.push_back(describe_unnumbered(r));
  EXPECT_EQ(got, expected);
  // The second run's first record: the answer that waited in the port.
  ASSERT_GT(set.sink.records.size(), alone_first.sink.records.size());
  const Record* answer = &set.sink.records[alone_first.sink.records.size()];
  ASSERT_EQ(answer->role, Role::kResponse);
  EXPECT_TRUE(answer->issues.has(IssueId::kUnsolicited));
  EXPECT_FALSE(answer->issues.has(IssueId::kLate));
  EXPECT_EQ(answer->txn, -1);
  const std::vector<std::string>& warnings = set.info.warnings;
  ASSERT_EQ(warnings.size(), 1U) << fmt::format("{}", fmt::join(warnings, " | "));
  EXPECT_NE(warnings[0].find("rec-0002.pcapng: the recording stopped at the end of "),
            std::string::npos)
      << warnings[0];
}

TEST(CaptureSet, PatternsAreExpandedByRtuscope) {
  TempDir dir;
  const auto a = dir.write("site-0001.pcapng", "x");
  const auto b = dir.write("site-0002.pcapng", "x");
  const auto odd = dir.write("odd[1].hex", "x");  // an existing name is taken as it is
  const std::string pattern = (dir.path() / "site-*.pcapng").string();
  EXPECT_EQ(expand_capture_paths({pattern}), (std::vector<std::string>{a, b}));
  EXPECT_EQ(expand_capture_paths({b, pattern}), (std::vector<std::string>{b, a}));
  EXPECT_EQ(expand_capture_paths({odd}), (std::vector<std::string>{odd}));
  EXPECT_EQ(expand_capture_paths({"no/such.hex"}), (std::vector<std::string>{"no/such.hex"}));
  try {
    (void)expand_capture_paths({(dir.path() / "none-*.pcapng").string()});
    FAIL() << "a pattern that matches nothing was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none-*.pcapng: no file matches"), std::string::npos);
  }
}

}  // namespace
}  // namespace rtu
