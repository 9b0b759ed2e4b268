#pragma once
// Several capture files read as one capture: the files of a rotated recording
// (`rtuscope live --rotate`), or any files that hold consecutive stretches of one line.
//
// The files are read in the order of their first timestamps (not of their names), each
// by the reader of its own format, and delivered through one CaptureConsumer as if they
// were one file: a transaction whose request ends one file and whose response starts the
// next is paired, silences across a boundary are timed as any other. Items keep the
// offsets (origins) of their own file.
//
// Where a file seems to be missing between two (capture/capture_set_gaps.hpp), a warning
// names both (capture_warnings()). Errors name both files and are thrown at the boundary,
// after everything before it was delivered:
//  * a file whose first record is earlier than the previous file's last (they overlap in
//    time: the same traffic twice, or two lines mixed);
//  * a file that declares other line settings than an earlier one.
// A file that cannot be opened, is empty or is damaged before its first record has no time;
// such files come last, in the order given, so the error names it after all else was read.
// A file damaged part-way, with files after it, loses only what follows its damage: the
// files after it are read on, across a break (as at a recording's end: nothing pairs across
// it), and the damage is thrown once they were, so the command still fails with it.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capture/capture_file.hpp"
#include "capture/capture_reader.hpp"
#include "capture/capture_warnings.hpp"
#include "core/input_error.hpp"

namespace rtu {

class CaptureSetReader final : public CaptureReader {
 public:
  using Opener =
      std::function<std::unique_ptr<CaptureReader>(const CaptureFile& file, WarningSink warnings)>;

  // Opens each file once to find its first timestamp (passing warnings silenced: they come
  // when the file is read). `open` defaults to open_capture (capture/open_capture.hpp).
  CaptureSetReader(const std::vector<CaptureFile>& files, WarningSink warnings,
                   Opener open = nullptr);
  ~CaptureSetReader() override;
  CaptureSetReader(const CaptureSetReader&) = delete;
  CaptureSetReader& operator=(const CaptureSetReader&) = delete;

  bool read(CaptureConsumer& to) override;
  // "site-0001.pcapng … site-0004.pcapng (4 files)", first and last in time order.
  [[nodiscard]] std::string name() const override;
  [[nodiscard]] std::optional<LineSettings> declared_settings() const override;
  [[nodiscard]] TimingKind timing_kind() const override;
  // The finest step of the files read so far.
  [[nodiscard]] Nanos timestamp_precision() const override { return precision_; }
  [[nodiscard]] std::optional<Nanos> declared_resolution() const override;
  [[nodiscard]] std::optional<Nanos> declared_timeout() const override;
  [[nodiscard]] bool holds_frames() const override;
  // Over the whole set: the files read through, plus the one being read.
  [[nodiscard]] std::uint64_t bytes_read() const override;
  [[nodiscard]] std::uint64_t input_size() const override;
  // Each file's own doubts, and where a file seems to be missing, in time order.
  [[nodiscard]] std::vector<std::string> capture_warnings() const override;

  // The files' names in the order they are read.
  [[nodiscard]] std::vector<std::string> paths() const;

 private:
  struct File;
  class Tap;
  void open_next();
  void close_current();
  // The current file is damaged (`error`) and files follow it: see the comment at the top.
  void skip_rest_after_damage(const InputError& error, CaptureConsumer& to);

  Opener open_;
  WarningSink warnings_;
  std::vector<File> files_;  // in time order
  std::size_t next_ = 0;     // the next file to open
  std::unique_ptr<CaptureReader> current_;
  // The last item delivered, from whichever file.
  std::optional<Nanos> last_time_;
  std::size_t last_file_ = 0;
  Nanos precision_ = 0;
  std::uint64_t bytes_done_ = 0;  // sizes of the files read through
  // The first damage of a file with files after it: thrown once they were read.
  std::optional<std::string> damage_;
};

}  // namespace rtu
