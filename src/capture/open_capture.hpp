#pragma once
// Opens a capture file with the right reader.
#include <memory>
#include <string>

#include "capture/capture_file.hpp"
#include "capture/capture_formats.hpp"
#include "capture/capture_reader.hpp"
#include "capture/capture_warnings.hpp"

namespace rtu {

// Chooses the format from the file's first bytes, falling back to its extension:
// - pcap or pcapng magic number → kPcap;
// - a first line that is a Saleae Logic export header (either layout, MP mode included so
//   that its reader can say why it refuses it) → kSaleaeCsv;
// - a first non-blank line that starts like a text hex line (a digit, sign, '.' or '#')
//   → kTextHex;
// - otherwise by extension (capture_formats(): .csv → kSaleaeCsv, .pcap/.pcapng/.cap → kPcap),
//   anything else → kTextHex, whose reader then says exactly where the content is not what
//   it expects.
// Throws InputError "NAME: cannot open: <strerror>" when the file cannot be read, and
// "NAME: the file is gzip-compressed; ..." (also zstd, xz, bzip2, zip, UTF-16 text) for files
// that no reader can use but people do hand over. The extension is the name's: a temporary
// copy of a piped input has none of its own.
CaptureFormat detect_capture_format(const CaptureFile& file);

// The reader for `file` (its format's factory in capture_formats()). Throws InputError when
// the file cannot be opened or its format has no reader here.
std::unique_ptr<CaptureReader> open_capture(const CaptureFile& file,
                                            WarningSink warnings = print_warning_to_stderr);

}  // namespace rtu
