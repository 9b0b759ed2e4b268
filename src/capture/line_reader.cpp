#include "capture/line_reader.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "core/input_error.hpp"

namespace rtu {
namespace {

constexpr std::size_t kTypicalLine = 4096;
static_assert(LineReader::kBufferSize <= LineReader::kMaxLineLength,
              "a line that buffered() holds whole is never too long");

}  // namespace

LineReader::LineReader(const CaptureFile& file) : name_(file.name), buffer_(new char[kBufferSize]) {
  line_.reserve(kTypicalLine);  // lines straddling two fills then need no allocation
  file_.reset(std::fopen(file.path.c_str(), "rb"));
  if (!file_) throw InputError(fmt::format("{}: cannot open: {}", name_, std::strerror(errno)));
  std::error_code error;
  const auto size = std::filesystem::file_size(file.path, error);
  if (!error) size_ = size;
}

bool LineReader::fill() {
  if (eof_) return false;
  const std::size_t n = std::fread(buffer_.get(), 1, kBufferSize, file_.get());
  if (n < kBufferSize) {
    if (std::ferror(file_.get()) != 0) {
      throw InputError(fmt::format("{}: read error after line {}: {}", name_, line_number_,
                                   std::strerror(errno)));
    }
    eof_ = true;
  }
  begin_ = 0;
  end_ = n;
  fetched_ += n;
  return n > 0;
}

bool LineReader::next(std::string_view& line) {
  line_.clear();
  bool continued = false;  // line_ holds the start of the current line
  for (;;) {
    if (begin_ == end_ && !fill()) {
      if (!continued) return false;  // clean end of file
      line = line_;                  // last line without '\n'
      break;
    }
    const char* start = buffer_.get() + begin_;
    const auto* newline = static_cast<const char*>(std::memchr(start, '\n', end_ - begin_));
    if (newline == nullptr) {
      // The line continues past this buffer: keep what we have and read on.
      line_.append(start, end_ - begin_);
      begin_ = end_;
      continued = true;
      if (line_.size() > kMaxLineLength) {
        throw InputError(fmt::format("{}:{}: line longer than {} characters", name_,
                                     line_number_ + 1, kMaxLineLength));
      }
      continue;
    }
    const auto length = static_cast<std::size_t>(newline - start);
    begin_ += length + 1;
    if (continued) {
      line_.append(start, length);
      line = line_;
    } else {
      line = std::string_view(start, length);  // the common case: no copy at all
    }
    break;
  }
  if (line.size() > kMaxLineLength) {
    throw InputError(fmt::format("{}:{}: line longer than {} characters", name_, line_number_ + 1,
                                 kMaxLineLength));
  }
  ++line_number_;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  // Editors on Windows start UTF-8 files with a byte-order mark; it is not content.
  constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
  if (line_number_ == 1 && line.substr(0, kUtf8Bom.size()) == kUtf8Bom) {
    line.remove_prefix(kUtf8Bom.size());
  }
  return true;
}

}  // namespace rtu
