#pragma once
// An input that can be read only once (standard input, a pipe, a FIFO, a process
// substitution such as /dev/fd/63), kept so that every pass over the capture can read it.
//
// A replay reads a capture more than once (a survey, then the decoding; `report` also reads
// a sample to identify devices), and the format is sniffed from the first bytes before the
// reader starts. A pipe gives its bytes only once, so it is read here exactly once, as it
// streams, into a temporary file that is unlinked at once: nothing is left behind however the
// run ends, and every pass reads the same bytes the same way as from a file given by path,
// so the output is the same byte for byte. The copy is in $TMPDIR, else /tmp.
#include <cstdint>
#include <functional>
#include <string>

#include "capture/capture_file.hpp"

namespace rtu {

struct SpoolOptions {
  // Where the copy goes; empty = $TMPDIR, else /tmp.
  std::string directory;
  // How long to wait for the first byte before saying what rtuscope waits for (a FIFO that
  // nobody writes to yet, a slow ssh); after that, it waits on.
  int quiet_wait_ms = 2000;
  // Told once when that wait is over, with a line to show the user.
  std::function<void(const std::string&)> on_waiting;
};

// Reads `fd` (which stays open) to its end into a temporary copy, named `name` in every
// message. Throws InputError naming `name`: "empty input" when it holds nothing; a read
// error; a copy that cannot be made or written (a full disk), naming the directory.
CaptureFile spool_input(int fd, const std::string& name, const SpoolOptions& options = {});

// The same for the path of a FIFO, a character device or a /dev/fd/N link: opened here
// (without blocking, so that a FIFO nobody writes to yet can be waited for with a word).
CaptureFile spool_input(const std::string& path, const SpoolOptions& options = {});

}  // namespace rtu
