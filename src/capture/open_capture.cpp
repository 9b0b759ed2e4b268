#include "capture/open_capture.hpp"

#include <fmt/format.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <utility>

#include "capture/saleae_reader.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

// Enough for any header line we recognise and a few blank lines before a text capture.
constexpr std::size_t kSniffSize = 4096;

bool is_pcap_magic(std::string_view head) {
  if (head.size() < 4) return false;
  static constexpr std::array<std::string_view, 5> kMagics = {
      std::string_view("\xD4\xC3\xB2\xA1", 4),  // pcap, µs, little-endian
      std::string_view("\xA1\xB2\xC3\xD4", 4),  // pcap, µs, big-endian
      std::string_view("\x4D\x3C\xB2\xA1", 4),  // pcap, ns, little-endian
      std::string_view("\xA1\xB2\x3C\x4D", 4),  // pcap, ns, big-endian
      std::string_view("\x0A\x0D\x0D\x0A", 4),  // pcapng Section Header Block
  };
  for (const auto magic : kMagics) {
    if (head.substr(0, 4) == magic) return true;
  }
  return false;
}

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

// Files people hand us that no reader can use; saying what they are beats "expected a
// timestamp, found '\x1f\x8b...'". Returns the explanation, or nothing.
std::string_view unusable_kind(std::string_view head) {
  struct Kind {
    std::string_view magic;
    std::string_view what;
  };
  static constexpr std::array<Kind, 7> kKinds = {{
      {std::string_view("\x1F\x8B", 2), "is gzip-compressed; decompress it first (zcat)"},
      {std::string_view("\x28\xB5\x2F\xFD", 4),
       "is zstd-compressed; decompress it first (zstdcat)"},
      {std::string_view("\xFD\x37\x7A\x58\x5A\x00", 6),
       "is xz-compressed; decompress it first (xzcat)"},
      {std::string_view("BZh", 3), "is bzip2-compressed; decompress it first (bzcat)"},
      {std::string_view("PK\x03\x04", 4), "is a zip archive; extract the capture first"},
      {std::string_view("\xFF\xFE", 2), "is UTF-16 text; save it as ASCII or UTF-8"},
      {std::string_view("\xFE\xFF", 2), "is UTF-16 text; save it as ASCII or UTF-8"},
  }};
  for (const auto& kind : kKinds) {
    if (starts_with(head, kind.magic)) return kind.what;
  }
  // UTF-16 without a byte-order mark: every other byte of ASCII text is zero.
  if (head.size() >= 4 && head[1] == '\0' && head[3] == '\0' && head[0] != '\0') {
    return "is UTF-16 text; save it as ASCII or UTF-8";
  }
  return {};
}

}  // namespace

CaptureFormat detect_capture_format(const CaptureFile& capture) {
  const std::string& name = capture.name;
  std::FILE* file = std::fopen(capture.path.c_str(), "rb");
  if (file == nullptr)
    throw InputError(fmt::format("{}: cannot open: {}", name, std::strerror(errno)));
  std::array<char, kSniffSize> buffer{};
  const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), file);
  const bool read_failed = std::ferror(file) != 0;
  const int read_errno = errno;
  std::fclose(file);
  if (read_failed)
    throw InputError(fmt::format("{}: cannot read: {}", name, std::strerror(read_errno)));
  std::string_view head(buffer.data(), n);

  if (is_pcap_magic(head)) return CaptureFormat::kPcap;
  if (const auto what = unusable_kind(head); !what.empty()) {
    throw InputError(
        fmt::format("{}: the file {}; expected a text hex capture or a Saleae Logic "
                    "CSV export",
                    name, what));
  }
  if (starts_with(head, "\xEF\xBB\xBF")) head.remove_prefix(3);  // UTF-8 byte-order mark
  const std::string_view first_line = head.substr(0, head.find('\n'));
  if (recognise_saleae_header(first_line) != SaleaeLayout::kNone) return CaptureFormat::kSaleaeCsv;
  const std::size_t first = head.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos) {
    const char c = head[first];
    if ((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == '#') {
      return CaptureFormat::kTextHex;
    }
  }
  if (const auto* by_extension = capture_format_for_path(name)) {
    return by_extension->factory.format;
  }
  return CaptureFormat::kTextHex;
}

std::unique_ptr<CaptureReader> open_capture(const CaptureFile& file, WarningSink warnings) {
  return capture_format(detect_capture_format(file)).factory.open(file, std::move(warnings));
}

}  // namespace rtu
