#pragma once
// The one contract of every capture file reader (text hex, Saleae CSV, pcap/pcapng): it
// delivers what the file holds, in file order, to a CaptureConsumer, and says what the file
// declares. The replay driver (pipeline/replay.hpp) reads every format through it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/chunk.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

// How the source's timestamps were taken; the framer treats them differently.
enum class TimingKind : std::uint8_t {
  kReadCompletion,  // t_end of each chunk = when read() returned (host serial reads)
  kPerByteExact,    // each chunk is one byte with measured timing (logic analysers)
};

// What a capture holds. Spans stay valid until the reader's next call.
class CaptureConsumer {
 public:
  virtual ~CaptureConsumer() = default;
  // Bytes as a receiver read them; the framer finds the frames.
  virtual void on_chunk(const Chunk& chunk) = 0;
  // Several one-byte reads in a row, delivered at once where a reader was asked to
  // (read_many(), or a ReadAhead's whole byte runs). The same as one on_chunk() per read,
  // which is what it does unless a consumer can take the run at once for less.
  virtual void on_byte_reads(const ByteReads& reads) {
    for (std::size_t i = 0; i < reads.size(); ++i) on_chunk(reads.read(i));
  }
  // Bytes whose frame boundaries the capture already knows (a frame, or bytes that form no
  // frame), starting at `t_start`; `origin` is where they are in the file.
  virtual void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) = 0;
  virtual void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start,
                        std::uint64_t origin) = 0;
  // The capture ended at `t` (where a live recording stopped).
  virtual void on_end(Nanos t) = 0;
};

class CaptureReader {
 public:
  virtual ~CaptureReader() = default;
  // Delivers the next item to `to` (exactly one call on it) and returns true, or returns false
  // at the end. Throws InputError on unusable input (with file:line or offset), after
  // delivering everything before the damage.
  virtual bool read(CaptureConsumer& to) = 0;
  // As read(), for a consumer that reads to the end and never stops between two reads (a
  // ReadAhead's reading thread): a reader that can may deliver several items in one call,
  // runs of one-byte reads among them as on_byte_reads(), up to `max_reads` reads in all.
  // Everything is delivered in file order, and what was read before damage is delivered
  // before the InputError is thrown.
  virtual bool read_many(CaptureConsumer& to, std::size_t max_reads) {
    (void)max_reads;
    return read(to);
  }

  // Name for messages and output headers (usually the path).
  [[nodiscard]] virtual std::string name() const = 0;
  // Line settings the input itself declares (e.g. "# baud=9600 parity=E stop=1").
  // Known once the first item was read (or the end reached).
  [[nodiscard]] virtual std::optional<LineSettings> declared_settings() const {
    return std::nullopt;
  }
  [[nodiscard]] virtual TimingKind timing_kind() const { return TimingKind::kReadCompletion; }
  // Finest step the timestamps are written with (e.g. 1 µs for 6 decimals); 0 = unknown.
  [[nodiscard]] virtual Nanos timestamp_precision() const { return 0; }
  // The timing resolution and response timeout the capture was decoded with, where it says
  // (rtuscope's own recordings and exports do), so a replay decides as that run did.
  [[nodiscard]] virtual std::optional<Nanos> declared_resolution() const { return std::nullopt; }
  [[nodiscard]] virtual std::optional<Nanos> declared_timeout() const { return std::nullopt; }
  // True when the format can hold frames with known boundaries (on_frame / on_noise). When
  // such a capture holds no chunks, its timing comes from those records, not from reads.
  [[nodiscard]] virtual bool holds_frames() const { return false; }
  // How far reading has got, in bytes of the input, and the input's size (0 = unknown): only
  // for showing progress. Approximate: readers read ahead through buffers.
  [[nodiscard]] virtual std::uint64_t bytes_read() const { return 0; }
  [[nodiscard]] virtual std::uint64_t input_size() const { return 0; }
  // Doubts about what was read so far that every output must state (e.g. records cut short);
  // complete at the end. Passing warnings (a clamped time) go to the reader's WarningSink.
  [[nodiscard]] virtual std::vector<std::string> capture_warnings() const { return {}; }
};

}  // namespace rtu
