#pragma once
// Reads a text file line by line through one fixed buffer, so memory stays flat however long
// the file is: after the longest line has been seen once, reading allocates nothing.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>

#include "capture/capture_file.hpp"

namespace rtu {

class LineReader {
 public:
  // Lines longer than this are unusable input (a text capture line holds one read() worth of
  // bytes, a CSV row one byte); the limit keeps a corrupt file from eating memory.
  static constexpr std::size_t kMaxLineLength = 1U << 20U;
  // The most a fill reads, and so the longest buffered() can be.
  static constexpr std::size_t kBufferSize = 64U * 1024U;

  // Opens `file`; throws InputError "NAME: cannot open: <strerror>" when that fails.
  explicit LineReader(const CaptureFile& file);

  // The next line without its '\n' (and without a '\r' before it; on line 1 without a UTF-8
  // byte-order mark). The view stays valid until
  // the next call. Returns false at the end of the file. Throws InputError on read errors and
  // on lines longer than kMaxLineLength.
  bool next(std::string_view& line);

  // The unread rest of the buffer, for a caller that reads lines in place: where it finds a
  // whole line there (up to and including its '\n') in a shape it knows, take_lines() consumes
  // it as next() would have returned it, without a look for the '\n' first or a copy. Empty
  // before the first fill and at the end of each; next() reads on. Never longer than
  // kMaxLineLength, so a line found in it whole is never too long.
  [[nodiscard]] std::string_view buffered() const {
    return {buffer_.get() + begin_, end_ - begin_};
  }
  // Consumes the first `length` characters of buffered(), `lines` whole lines with their '\n'.
  void take_lines(std::size_t length, std::size_t lines) {
    begin_ += length;
    line_number_ += lines;
  }

  // 1-based number of the line last returned by next() or taken.
  [[nodiscard]] std::uint64_t line_number() const { return line_number_; }
  // What messages call the file (CaptureFile::name).
  [[nodiscard]] const std::string& name() const { return name_; }
  // Bytes of the file up to the end of the line last returned (for progress), and the file's
  // size when it was opened (0 when it cannot be told, e.g. a pipe).
  [[nodiscard]] std::uint64_t bytes_read() const { return fetched_ - (end_ - begin_); }
  [[nodiscard]] std::uint64_t size() const { return size_; }

 private:
  bool fill();

  struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::string name_;
  std::unique_ptr<std::FILE, FileCloser> file_;
  std::unique_ptr<char[]> buffer_;
  std::size_t begin_ = 0;  // unread data in buffer_ is [begin_, end_)
  std::size_t end_ = 0;
  bool eof_ = false;
  std::string line_;  // holds a line that straddles two buffer fills
  std::uint64_t line_number_ = 0;
  std::uint64_t fetched_ = 0;  // bytes read from the file into buffer_ so far
  std::uint64_t size_ = 0;
};

}  // namespace rtu
