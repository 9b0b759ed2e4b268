#pragma once
// A ByteOutput for a named pipe another program reads live (Wireshark's extcap FIFO): every
// unit goes to the pipe at once, so the reader sees each record as soon as it is written.
// When the reader closes its end (EPIPE), the output turns into a sink that drops what
// comes after, and says so through reader_gone(): the capture then stops; nobody is left
// to receive the bytes. The process must ignore SIGPIPE for that to be seen.
#include <cstdint>
#include <span>
#include <string>

#include "capture/byte_output.hpp"

namespace rtu {

class PipeOutput final : public ByteOutput {
 public:
  // Opens `path` for writing; for a FIFO this waits until the reader has opened it.
  // Throws InputError naming the path when it cannot be opened.
  explicit PipeOutput(std::string path);
  ~PipeOutput() override;
  PipeOutput(const PipeOutput&) = delete;
  PipeOutput& operator=(const PipeOutput&) = delete;

  // Throws InputError naming the path for write errors other than a closed reader.
  void write(std::span<const std::uint8_t> unit) override;
  void flush() override {}  // nothing is held back

  // True once the reader has closed the pipe: seen by a failed write or by polling the
  // pipe, so an idle line still notices it.
  [[nodiscard]] bool reader_gone();
  // Units dropped because the reader was gone.
  [[nodiscard]] std::uint64_t dropped_units() const { return dropped_; }

 private:
  std::string path_;
  int fd_ = -1;
  bool gone_ = false;
  std::uint64_t dropped_ = 0;
};

}  // namespace rtu
