#pragma once
// Anything that yields timed chunks: capture file readers, live serial ports.
#include <optional>
#include <string>

#include "core/chunk.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

// How the source's timestamps were taken; the framer treats them differently.
enum class TimingKind : std::uint8_t {
  kReadCompletion,  // t_end of each chunk = when read() returned (host serial reads)
  kPerByteExact,    // each chunk is one byte with measured timing (logic analysers)
};

class ChunkSource {
 public:
  virtual ~ChunkSource() = default;
  // Fills `out` with the next chunk; its spans stay valid until the next call.
  // Returns false at the end. Throws InputError on unusable input (with file:line).
  virtual bool next(Chunk& out) = 0;
  // Line settings the input itself declares (e.g. "# baud=9600 parity=E stop=1").
  // Known once the first chunk was read (or the end reached).
  [[nodiscard]] virtual std::optional<LineSettings> declared_settings() const {
    return std::nullopt;
  }
  [[nodiscard]] virtual TimingKind timing_kind() const { return TimingKind::kReadCompletion; }
  // Finest step the timestamps are written with (e.g. 1 µs for 6 decimals); 0 = unknown.
  [[nodiscard]] virtual Nanos timestamp_precision() const { return 0; }
  // Name for messages and output headers (usually the path).
  [[nodiscard]] virtual std::string name() const = 0;
};

}  // namespace rtu
