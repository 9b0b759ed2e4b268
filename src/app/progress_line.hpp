#pragma once
// The progress line of `decode`, `report` and `export` on a long capture: how far each pass
// over the file has got, its rate and ETA, on stderr, redrawn in place a few times a second
// and erased at the end or when an error ends the command. Shown only where a person watches
// (stderr is a terminal) and the wait is worth a line (an input of kMinInputSize or more);
// never in pipes or files, never with --quiet.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <string>

#include "pipeline/replay.hpp"

namespace rtu::app {

// Adds --quiet (no progress line) to a command.
void add_quiet_flag(CLI::App& command, bool& quiet);

// False with --quiet, and when `output` is standard output on a terminal: records written
// there while the line is redrawn would garble both.
[[nodiscard]] bool progress_wanted(bool quiet, const std::string& output);

class ProgressLine {
 public:
  // Smaller inputs are read in a moment; a line would only flicker.
  static constexpr std::uint64_t kMinInputSize = 4U * 1024U * 1024U;

  explicit ProgressLine(bool wanted);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;
  ProgressLine(ProgressLine&&) = delete;
  ProgressLine& operator=(ProgressLine&&) = delete;

  // The next replay_capture with `options` shows its two passes over the file as
  // "<label> 1/2" (learning the timing) and "<label> 2/2" (the work itself), or its one pass
  // as "<label> 1/1" where the timing is learned alongside (decode_and_survey).
  void attach(ReplayOptions& options, std::string label);
  // Takes the line off the terminal, before the command writes there.
  void erase();

 private:
  using Clock = std::chrono::steady_clock;
  void update(const ReplayProgress& progress);
  void draw(const std::string& text);

  bool wanted_;
  std::string label_;
  ReplayProgress::Pass pass_ = ReplayProgress::Pass::kSurvey;
  Clock::time_point pass_start_;
  Clock::time_point last_draw_;
  std::uint64_t bytes_ = 0;  // the most seen in this pass: the line never goes back
  bool on_screen_ = false;
};

}  // namespace rtu::app
