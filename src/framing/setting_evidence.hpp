#pragma once
// What listening at one line setting showed: the evidence `rtuscope probe` ranks candidate
// settings by. The bytes go through the same Framer as every other command, so a frame
// counts here exactly when decode would call it CRC-valid.
#include <cstdint>

#include "core/chunk.hpp"
#include "framing/framer.hpp"
#include "framing/record.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

struct SettingEvidence {
  LineSettings line;
  Nanos listened = 0;
  std::uint64_t bytes = 0;  // bytes received, an error-marked one counted once
  std::uint64_t parity_errors = 0;
  std::uint64_t framing_errors = 0;
  std::uint64_t breaks = 0;
  std::uint64_t frames = 0;       // CRC-valid frames
  std::uint64_t frame_bytes = 0;  // bytes in them
  // Error-marked bytes inside CRC-valid frames: the bytes are right, the setting is not
  // (the wrong parity reads every byte right and flags it).
  std::uint64_t flagged_frame_bytes = 0;
  // Bursts: bytes between silences. On a swapped pair the line idles low, so the last
  // character of every burst sees a low stop bit: each burst ends in an error or a break,
  // at any baud. A straight line at a wrong setting ends only some bursts so.
  std::uint64_t bursts = 0;
  std::uint64_t bursts_ending_flagged = 0;
  // Single bytes between frames, and how many of them are 00 or FF: what a line without
  // fail-safe bias gives at turnarounds, when the idle line floats.
  std::uint64_t lone_bytes = 0;
  std::uint64_t lone_idle_bytes = 0;

  [[nodiscard]] std::uint64_t line_errors() const {
    return parity_errors + framing_errors + breaks;
  }
  [[nodiscard]] std::uint64_t noise_bytes() const { return bytes - frame_bytes; }
  [[nodiscard]] double frames_per_second() const;
  // Share of the bytes that CRC-valid frames explain without a line error, 0..1.
  [[nodiscard]] double clean_share() const;
  // CRC-valid frames per second, scaled by the clean share: 0 when nothing fits.
  [[nodiscard]] double score() const;
  // Frames that leave no doubt: enough of them, no error inside any, and most bytes
  // explained (lone glitch bytes between frames do not make a setting wrong).
  [[nodiscard]] bool reads_clean() const;
};

// Feeds the chunks read at one setting through a Framer and counts what it finds.
class EvidenceCounter final : public RecordSink {
 public:
  // `resolution`: the port's timing resolution (SerialStatus::resolution).
  EvidenceCounter(const LineSettings& line, Nanos resolution);
  void push(const Chunk& chunk);
  // Enough exchanges heard that listening on cannot change the verdict: the setting reads
  // them clean (SettingEvidence::reads_clean), or it found no frame at all. Counted in bursts,
  // not time, so a slow bus gets as many chances as a fast one.
  [[nodiscard]] bool settled() const;
  // Ends the listening (what is buffered is decided) and returns the evidence.
  // `stopped_at`: when listening stopped (the chunks' clock); a burst still going on then
  // was cut, its real end unseen, and is left out. kUnknownTime counts it.
  SettingEvidence finish(Nanos listened, Nanos stopped_at = kUnknownTime);

 private:
  void on_record(Record& record) override;
  void end_burst();

  SettingEvidence evidence_;
  Nanos silence_;  // a gap this long between reads ends a burst
  Nanos last_end_ = kUnknownTime;
  bool last_flagged_ = false;
  Framer framer_;  // last: it holds a reference to this sink
};

}  // namespace rtu
