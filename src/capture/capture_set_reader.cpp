#include "capture/capture_set_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string_view>
#include <utility>

#include "capture/capture_set_gaps.hpp"
#include "capture/open_capture.hpp"
#include "core/input_error.hpp"
#include "core/time_format.hpp"

namespace rtu {

struct CaptureSetReader::File {
  explicit File(CaptureFile file) : input(std::move(file)) {}
  CaptureFile input;
  // From the first look: the first item's time (none when the file is empty or unreadable)
  // and what the file declares.
  std::optional<Nanos> first;
  std::optional<LineSettings> declared;
  std::optional<Nanos> resolution;
  std::optional<Nanos> timeout;
  TimingKind timing = TimingKind::kReadCompletion;
  bool holds_frames = false;
  std::uint64_t size = 0;  // input_size(): what the progress line counts
  // While it is read:
  std::optional<Nanos> last;
  Nanos longest_silence = 0;  // between consecutive items (their timestamps)
  bool ended = false;         // its last item so far is the recording's end
  // From the last item before it (of file `previous`) to its first.
  std::optional<Nanos> silence_before;
  std::size_t previous = 0;
  std::vector<std::string> warnings;  // its capture_warnings(), once read through
};

// Forwards each item (when there is a consumer) and keeps its time.
class CaptureSetReader::Tap final : public CaptureConsumer {
 public:
  explicit Tap(CaptureConsumer* to) : to_(to) {}
  void on_chunk(const Chunk& chunk) override {
    t = chunk.t_end;
    if (to_ != nullptr) to_->on_chunk(chunk);
  }
  void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) override {
    t = t_start;
    if (to_ != nullptr) to_->on_frame(adu, t_start, origin);
  }
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) override {
    t = t_start;
    if (to_ != nullptr) to_->on_noise(bytes, t_start, origin);
  }
  void on_end(Nanos end) override {
    t = end;
    ended = true;
    if (to_ != nullptr) to_->on_end(end);
  }
  Nanos t = 0;
  bool ended = false;  // the item was the recording's end

 private:
  CaptureConsumer* to_;
};

namespace {

// "2026-11-23 08:43:45.420647 UTC" for wall-clock times, else "12.345678 s".
std::string time_text(Nanos t) {
  fmt::memory_buffer b;
  if (t >= kWallClockFrom) {
    append_utc_date(b, t);
    b.push_back(' ');
    append_utc_time_of_day(b, t, 6);
    b.append(std::string_view(" UTC"));
  } else {
    append_seconds(b, t, 6);
    b.append(std::string_view(" s"));
  }
  return fmt::to_string(b);
}

bool same_line(const LineSettings& a, const LineSettings& b) {
  return a.baud == b.baud && a.parity == b.parity && a.stop_bits == b.stop_bits;
}

}  // namespace

CaptureSetReader::CaptureSetReader(const std::vector<CaptureFile>& inputs, WarningSink warnings,
                                   Opener open)
    : open_(std::move(open)), warnings_(std::move(warnings)) {
  if (!open_) {
    open_ = [](const CaptureFile& input, WarningSink sink) {
      return open_capture(input, std::move(sink));
    };
  }
  files_.reserve(inputs.size());
  for (const auto& input : inputs) {
    File file(input);
    try {
      const auto reader = open_(input, [](std::string_view) {});
      Tap first(nullptr);
      if (reader->read(first)) file.first = first.t;
      file.declared = reader->declared_settings();
      file.resolution = reader->declared_resolution();
      file.timeout = reader->declared_timeout();
      file.timing = reader->timing_kind();
      file.holds_frames = reader->holds_frames();
      file.size = reader->input_size();
    } catch (const InputError&) {
      // Placed last; reading it there raises the same error, after all else was delivered.
    }
    files_.push_back(std::move(file));
  }
  std::stable_sort(files_.begin(), files_.end(), [](const File& a, const File& b) {
    if (a.first && b.first) return *a.first < *b.first;
    return a.first.has_value() && !b.first.has_value();
  });
}

CaptureSetReader::~CaptureSetReader() = default;

bool CaptureSetReader::read(CaptureConsumer& to) {
  for (;;) {
    if (!current_) {
      if (next_ == files_.size()) {
        if (damage_) {
          const std::string message = std::move(*damage_);
          damage_.reset();
          throw InputError(message);
        }
        return false;
      }
      open_next();
    }
    Tap tap(&to);
    bool more = false;
    try {
      more = current_->read(tap);
    } catch (const InputError& error) {
      if (next_ == files_.size()) throw;  // the last file's damage ends the capture there
      skip_rest_after_damage(error, to);
      continue;
    }
    if (!more) {
      close_current();
      continue;
    }
    const std::size_t index = next_ - 1;
    File& file = files_[index];
    if (file.last) file.longest_silence = std::max(file.longest_silence, tap.t - *file.last);
    file.last = tap.t;
    file.ended = tap.ended;
    last_time_ = tap.t;
    last_file_ = index;
    const Nanos precision = current_->timestamp_precision();
    if (precision > 0 && (precision_ == 0 || precision < precision_)) precision_ = precision;
    return true;
  }
}

void CaptureSetReader::open_next() {
  const std::size_t index = next_;
  File& file = files_[index];
  // Another line first: when files of two lines also overlap, that is the cause.
  if (file.declared) {
    for (std::size_t i = 0; i < index; ++i) {
      const auto& earlier = files_[i].declared;
      if (!earlier) continue;
      if (!same_line(*earlier, *file.declared)) {
        throw InputError(fmt::format(
            "{}: declares the line {}, but {} declares {}: the files of one capture share "
            "one line",
            file.input.name, file.declared->describe(), files_[i].input.name, earlier->describe()));
      }
      break;
    }
  }
  if (file.first && last_time_) {
    const File& before = files_[last_file_];
    if (*file.first < *last_time_) {
      throw InputError(fmt::format(
          "{}: its first record ({}) is earlier than the last record of {} ({}): the files "
          "overlap in time, so they are not consecutive files of one capture",
          file.input.name, time_text(*file.first), before.input.name, time_text(*last_time_)));
    }
    file.silence_before = *file.first - *last_time_;
    file.previous = last_file_;
  }
  ++next_;
  current_ = open_(file.input, warnings_);
}

void CaptureSetReader::skip_rest_after_damage(const InputError& error, CaptureConsumer& to) {
  const File& file = files_[next_ - 1];
  if (!damage_) {
    damage_ = fmt::format("{} (the rest of {} was skipped; the files after it were read)",
                          error.what(), file.input.name);
  }
  close_current();
  // What the damage took is a stretch of unknown length: a break, as a recording's end.
  if (file.last) to.on_end(*file.last);
}

void CaptureSetReader::close_current() {
  files_[next_ - 1].warnings = current_->capture_warnings();
  bytes_done_ += files_[next_ - 1].size;
  current_.reset();
}

std::uint64_t CaptureSetReader::bytes_read() const {
  return bytes_done_ + (current_ ? current_->bytes_read() : 0);
}

std::uint64_t CaptureSetReader::input_size() const {
  std::uint64_t total = 0;
  for (const File& f : files_) total += f.size;
  return total;
}

std::string CaptureSetReader::name() const {
  if (files_.empty()) return {};
  return fmt::format("{} \u2026 {} ({} files)", files_.front().input.name, files_.back().input.name,
                     files_.size());
}

std::optional<LineSettings> CaptureSetReader::declared_settings() const {
  for (std::size_t i = 0; i < next_; ++i) {
    if (files_[i].declared) return files_[i].declared;
  }
  return std::nullopt;
}

TimingKind CaptureSetReader::timing_kind() const {
  return files_.empty() ? TimingKind::kReadCompletion : files_.front().timing;
}

std::optional<Nanos> CaptureSetReader::declared_resolution() const {
  for (std::size_t i = 0; i < next_; ++i) {
    if (files_[i].resolution) return files_[i].resolution;
  }
  return std::nullopt;
}

std::optional<Nanos> CaptureSetReader::declared_timeout() const {
  for (std::size_t i = 0; i < next_; ++i) {
    if (files_[i].timeout) return files_[i].timeout;
  }
  return std::nullopt;
}

bool CaptureSetReader::holds_frames() const {
  return std::any_of(files_.begin(), files_.end(), [](const File& f) { return f.holds_frames; });
}

std::vector<std::string> CaptureSetReader::capture_warnings() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < next_; ++i) {
    const File& file = files_[i];
    if (file.silence_before) {
      const File& before = files_[file.previous];
      SetBoundary boundary;
      boundary.before = before.input.name;
      boundary.after = file.input.name;
      boundary.silence = *file.silence_before;
      boundary.longest_within = std::max(before.longest_silence, file.longest_silence);
      boundary.before_ended = before.ended;
      if (auto warning = missing_file_warning(boundary)) out.push_back(std::move(*warning));
    }
    const bool reading = current_ && i + 1 == next_;
    for (auto& w : reading ? current_->capture_warnings() : file.warnings) out.push_back(w);
  }
  return out;
}

std::vector<std::string> CaptureSetReader::paths() const {
  std::vector<std::string> out;
  out.reserve(files_.size());
  for (const auto& file : files_) out.push_back(file.input.name);
  return out;
}

}  // namespace rtu
