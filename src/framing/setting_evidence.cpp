#include "framing/setting_evidence.hpp"

#include <algorithm>

namespace rtu {
namespace {

FramerConfig framer_config(const LineSettings& line, Nanos resolution) {
  FramerConfig config;
  config.line = line;
  config.resolution = resolution;
  return config;
}

}  // namespace

double SettingEvidence::frames_per_second() const {
  if (listened <= 0) return 0.0;
  return static_cast<double>(frames) * 1e9 / static_cast<double>(listened);
}

double SettingEvidence::clean_share() const {
  if (bytes == 0) return 0.0;
  const std::uint64_t clean = frame_bytes - std::min(frame_bytes, flagged_frame_bytes);
  return static_cast<double>(clean) / static_cast<double>(bytes);
}

double SettingEvidence::score() const {
  return frames_per_second() * clean_share();
}

EvidenceCounter::EvidenceCounter(const LineSettings& line, Nanos resolution)
    :  // t3.5, but never below what the read times can show.
      silence_(std::max(line.t3_5(), 2 * resolution)),
      framer_(framer_config(line, resolution), *this) {
  evidence_.line = line;
}

void EvidenceCounter::end_burst() {
  if (last_end_ == kUnknownTime) return;
  ++evidence_.bursts;
  if (last_flagged_) ++evidence_.bursts_ending_flagged;
}

void EvidenceCounter::push(const Chunk& chunk) {
  if (chunk.bytes.empty()) return;
  if (last_end_ != kUnknownTime &&
      chunk.t_end - last_end_ >
          silence_ + evidence_.line.char_time() * static_cast<Nanos>(chunk.bytes.size())) {
    end_burst();
  }
  last_end_ = chunk.t_end;
  last_flagged_ = !chunk.errors.empty() && chunk.errors.back() != kLineOk;
  evidence_.bytes += chunk.bytes.size();
  for (const auto e : chunk.errors) {
    if ((e & kBreak) != 0) {
      ++evidence_.breaks;
    } else if ((e & kFramingError) != 0) {
      ++evidence_.framing_errors;
    } else if ((e & kParityError) != 0) {
      ++evidence_.parity_errors;
    }
  }
  framer_.push(chunk);
}

bool SettingEvidence::reads_clean() const {
  return frames >= 3 && flagged_frame_bytes == 0 && clean_share() >= 0.8;
}

bool EvidenceCounter::settled() const {
  constexpr std::uint64_t kSettlingBursts = 8;
  if (evidence_.bursts < kSettlingBursts) return false;
  return evidence_.frames == 0 || evidence_.reads_clean();
}

SettingEvidence EvidenceCounter::finish(Nanos listened, Nanos stopped_at) {
  framer_.finish();
  if (stopped_at == kUnknownTime || last_end_ == kUnknownTime ||
      stopped_at - last_end_ > silence_) {
    end_burst();
  }
  last_end_ = kUnknownTime;
  evidence_.listened = listened;
  return evidence_;
}

void EvidenceCounter::on_record(Record& record) {
  if (record.size == 1 && !record.crc_ok) {
    ++evidence_.lone_bytes;
    if (record.storage[0] == 0x00 || record.storage[0] == 0xFF) ++evidence_.lone_idle_bytes;
  }
  if (record.kind != RecordKind::kFrame || !record.crc_ok) return;
  ++evidence_.frames;
  evidence_.frame_bytes += record.size;
  // A record keeps only the union of its bytes' flags: one flag marks the whole frame.
  if (record.line_errors != 0) evidence_.flagged_frame_bytes += record.size;
}

}  // namespace rtu
