#include "app/progress_line.hpp"

#include <fmt/format.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <utility>

#include "report/progress_text.hpp"

namespace rtu::app {
namespace {

// At most four redraws a second: readable, and the terminal is no bottleneck.
constexpr auto kRedrawEvery = std::chrono::milliseconds(250);

// Columns of the terminal on stderr; 80 when it does not say.
std::size_t terminal_width() {
  winsize size{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  return 80;
}

}  // namespace

void add_quiet_flag(CLI::App& command, bool& quiet) {
  command.add_flag("-q,--quiet", quiet,
                   "No progress line (otherwise shown on a terminal for captures of 4 MB or more)");
}

bool progress_wanted(bool quiet, const std::string& output) {
  return !quiet && !(output == "-" && ::isatty(STDOUT_FILENO) == 1);
}

ProgressLine::ProgressLine(bool wanted) : wanted_(wanted && ::isatty(STDERR_FILENO) == 1) {}

ProgressLine::~ProgressLine() {
  erase();
}

void ProgressLine::attach(ReplayOptions& options, std::string label) {
  if (!wanted_) return;
  label_ = std::move(label);
  pass_ = ReplayProgress::Pass::kSurvey;
  pass_start_ = Clock::now();
  bytes_ = 0;
  options.on_progress = [this](const ReplayProgress& progress) { update(progress); };
}

void ProgressLine::update(const ReplayProgress& progress) {
  if (progress.input_size < kMinInputSize) return;
  const auto now = Clock::now();
  if (progress.pass != pass_) {
    // The decoding pass began when the survey ended (see below), not at its first report.
    pass_ = progress.pass;
    bytes_ = 0;
  }
  bytes_ = std::max(bytes_, progress.bytes_read);
  // The last report of a pass is always drawn, so every pass is seen to finish.
  if (!progress.pass_done && on_screen_ && now - last_draw_ < kRedrawEvery) return;
  const bool decoding = progress.pass == ReplayProgress::Pass::kDecode;
  const std::string label = progress.only_pass ? fmt::format("{} 1/1", label_)
                                               : fmt::format("{} {}/2", label_, decoding ? 2 : 1);
  ProgressFigures figures;
  figures.label = label;
  figures.bytes = bytes_;
  figures.size = progress.input_size;
  figures.records = progress.records;
  figures.seconds = std::chrono::duration<double>(now - pass_start_).count();
  draw(progress_text(figures));
  last_draw_ = now;
  if (progress.pass_done) pass_start_ = Clock::now();
}

void ProgressLine::draw(const std::string& text) {
  // A line longer than the terminal would wrap, and '\r' would then redraw only its tail.
  const std::size_t width = terminal_width() - 1;
  const std::string_view shown = std::string_view(text).substr(0, width);
  // The cursor goes back to the line's start: a warning printed meanwhile writes over the
  // line instead of after it.
  fmt::print(stderr, "\r{}\x1b[K\r", shown);
  std::fflush(stderr);
  on_screen_ = true;
}

void ProgressLine::erase() {
  if (!on_screen_) return;
  std::fputs("\r\x1b[K", stderr);
  std::fflush(stderr);
  on_screen_ = false;
}

}  // namespace rtu::app
