#pragma once
// Test helper: lays frames out on a simulated line with exact byte times, then cuts the
// byte stream into chunks the way a per-byte source or a batching USB adapter would.
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "core/chunk.hpp"
#include "core/crc16.hpp"
#include "framing/record.hpp"
#include "serial/line_settings.hpp"

namespace rtu::test {

inline std::vector<std::uint8_t> with_crc(std::vector<std::uint8_t> adu) {
  const std::uint16_t crc = crc16(adu);
  adu.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  adu.push_back(static_cast<std::uint8_t>(crc >> 8U));
  return adu;
}
inline std::vector<std::uint8_t> with_crc(std::initializer_list<std::uint8_t> body) {
  return with_crc(std::vector<std::uint8_t>(body));
}

// One-byte reads (each chunk's byte and its stamp) side by side, as a per-byte replay hands
// runs of them over (ByteReads).
struct ByteRun {
  explicit ByteRun(const std::vector<Chunk>& reads) {
    for (const Chunk& read : reads) {
      bytes.push_back(read.bytes[0]);
      t_ends.push_back(read.t_end);
    }
  }
  // Reads [first, first + size) as one run, the first of them numbered `origin`.
  [[nodiscard]] ByteReads slice(std::size_t first, std::size_t size, std::uint64_t origin) const {
    return ByteReads{std::span(bytes).subspan(first, size), t_ends.data() + first, origin, 0};
  }
  std::vector<std::uint8_t> bytes;
  std::vector<Nanos> t_ends;
};

class BusBuilder {
 public:
  explicit BusBuilder(LineSettings line = {}) : line_(line) {}

  // Appends bytes after `silence` of idle line; bytes follow back to back.
  BusBuilder& add(const std::vector<std::uint8_t>& bytes, Nanos silence) {
    Nanos t = end_ + silence;
    added_.push_back(bytes_.size());
    for (const auto b : bytes) {
      bytes_.push_back(b);
      t += line_.char_time();
      ends_.push_back(t);
    }
    end_ = t;
    return *this;
  }

  // One chunk per byte, stamped with the end of that byte (an exact per-byte source).
  [[nodiscard]] std::vector<Chunk> per_byte() const {
    std::vector<Chunk> out;
    for (std::size_t i = 0; i < bytes_.size(); ++i) {
      Chunk c;
      c.t_end = ends_[i];
      c.bytes = std::span(bytes_).subspan(i, 1);
      c.origin = i + 1;
      out.push_back(c);
    }
    return out;
  }

  // One chunk per add(), stamped with the end of its last byte: a read per frame, as from a
  // source whose reads the silences between frames cut.
  [[nodiscard]] std::vector<Chunk> per_add() const {
    std::vector<Chunk> out;
    for (std::size_t k = 0; k < added_.size(); ++k) {
      const std::size_t first = added_[k];
      const std::size_t end = k + 1 < added_.size() ? added_[k + 1] : bytes_.size();
      if (end == first) continue;
      Chunk c;
      c.t_end = ends_[end - 1];
      c.bytes = std::span(bytes_).subspan(first, end - first);
      c.origin = first + 1;
      out.push_back(c);
    }
    return out;
  }

  // The same as one run of one-byte reads (as a per-byte replay hands them over), valid
  // while this builder lives and nothing is added to it.
  [[nodiscard]] ByteReads byte_reads() const { return ByteReads{bytes_, ends_.data(), 1, 0}; }

  // A USB adapter: every `period` it delivers whatever arrived since its last delivery.
  [[nodiscard]] std::vector<Chunk> batched(Nanos period) const {
    std::vector<Chunk> out;
    std::size_t i = 0;
    Nanos deadline = kStart + period;
    while (i < bytes_.size()) {
      std::size_t j = i;
      while (j < bytes_.size() && ends_[j] <= deadline) ++j;
      if (j > i) {
        Chunk c;
        c.t_end = deadline;
        c.bytes = std::span(bytes_).subspan(i, j - i);
        c.origin = out.size() + 1;
        out.push_back(c);
        i = j;
      }
      deadline += period;
    }
    return out;
  }

  // A USB adapter with a latency timer, as rtuvbus models it: the first byte into an
  // empty buffer starts the timer; the buffer goes out when the timer runs out or when
  // `packet` bytes are waiting.
  [[nodiscard]] std::vector<Chunk> usb(Nanos latency, std::size_t packet) const {
    std::vector<Chunk> out;
    std::size_t first = 0;
    while (first < bytes_.size()) {
      const Nanos deadline = ends_[first] + latency;
      std::size_t j = first;
      while (j < bytes_.size() && ends_[j] <= deadline && j - first < packet) ++j;
      Chunk c;
      c.t_end = j - first == packet ? ends_[j - 1] : deadline;
      c.bytes = std::span(bytes_).subspan(first, j - first);
      c.origin = out.size() + 1;
      out.push_back(c);
      first = j;
    }
    return out;
  }

  // An adapter that sends once the line has been idle for `idle` after the last byte it
  // holds (a UART's character timeout, CH34x-like chips), or as soon as `packet` bytes wait.
  [[nodiscard]] std::vector<Chunk> idle_flush(Nanos idle, std::size_t packet) const {
    std::vector<Chunk> out;
    std::size_t first = 0;
    while (first < bytes_.size()) {
      std::size_t j = first + 1;
      // The next byte joins the packet when it starts before the idle wait ran out.
      while (j < bytes_.size() && j - first < packet &&
             ends_[j] - line_.char_time() < ends_[j - 1] + idle) {
        ++j;
      }
      Chunk c;
      c.t_end = j - first == packet ? ends_[j - 1] : ends_[j - 1] + idle;
      c.bytes = std::span(bytes_).subspan(first, j - first);
      c.origin = out.size() + 1;
      out.push_back(c);
      first = j;
    }
    return out;
  }

  [[nodiscard]] const LineSettings& line() const { return line_; }
  [[nodiscard]] std::size_t size() const { return bytes_.size(); }

 private:
  LineSettings line_;
  std::vector<std::uint8_t> bytes_;
  std::vector<Nanos> ends_;
  std::vector<std::size_t> added_;  // where each add()'s bytes begin
  static constexpr Nanos kStart = 1 * kNanosPerSecond;
  Nanos end_ = kStart;
};

// Collects everything a pipeline emits.
class CollectingSink : public RecordSink {
 public:
  void on_record(Record& record) override {
    records.push_back(record);
    if (record.request != nullptr) requests_of_responses.push_back(*record.request);
  }
  void on_finish() override { finished = true; }

  [[nodiscard]] std::size_t frames() const {
    std::size_t n = 0;
    for (const auto& r : records) n += r.kind == RecordKind::kFrame ? 1 : 0;
    return n;
  }
  [[nodiscard]] std::size_t total_bytes() const {
    std::size_t n = 0;
    for (const auto& r : records) n += r.size;
    return n;
  }

  std::vector<Record> records;
  std::vector<Record> requests_of_responses;
  bool finished = false;
};

}  // namespace rtu::test
