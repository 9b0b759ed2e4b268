#pragma once
// One streaming reader for classic pcap and pcapng files: either byte order, µs or ns
// pcap magic, pcapng if_tsresol (10^-n and 2^-n) and if_tsoffset, several sections and
// interfaces; unknown block types are skipped by their length. Memory is bounded by the
// largest block (≤ pcap::kMaxRecordSize).
//
// Damage: packets are delivered in file order, so everything before damage has been
// delivered when next() throws InputError("<name>: offset <n>: <what was expected>").
// After that next() returns false.
#include <cstdint>
#include <istream>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "capture/capture_file.hpp"
#include "core/time.hpp"

namespace rtu {

enum class CaptureFileFormat : std::uint8_t { kPcap, kPcapng };

struct CapturePacket {
  std::uint16_t link_type = 0;
  std::uint32_t interface_id = 0;  // index within its section (classic pcap: 0)
  std::uint32_t section = 0;       // pcapng section, counting from 0 (classic pcap: 0)
  Nanos t = 0;                     // ns since 1970-01-01 UTC, if_tsoffset applied
  Nanos resolution = 0;            // timestamp step of its interface, ns (≥ 1)
  std::uint32_t original_length = 0;
  std::optional<std::uint32_t> flags;  // epb_flags when present
  std::uint64_t offset = 0;            // byte offset of the packet's block / record header
  // Views valid until the next call to next():
  std::span<const std::uint8_t> data;
  std::string_view comment;  // opt_comment(s), joined by "\n"; empty when none
  std::string_view interface_name;
  std::string_view interface_description;
};

class PcapReader {
 public:
  // `accepted_link_types`: packets on other link types throw InputError naming the offset
  // of the interface (IDB or pcap header) that declared them; empty = accept all.
  // Throws InputError if the file cannot be opened or is neither pcap nor pcapng.
  explicit PcapReader(const CaptureFile& file, std::vector<std::uint16_t> accepted_link_types = {});
  PcapReader(std::unique_ptr<std::istream> in, std::string name,
             std::vector<std::uint16_t> accepted_link_types = {});
  ~PcapReader();
  PcapReader(const PcapReader&) = delete;
  PcapReader& operator=(const PcapReader&) = delete;

  // Fills `out` with the next packet; false at the clean end of the file.
  bool next(CapturePacket& out);

  [[nodiscard]] CaptureFileFormat format() const;
  [[nodiscard]] const std::string& name() const;
  // The description of the first interface of an accepted link type read so far, empty if
  // none: what a file without packets still says about its line.
  [[nodiscard]] const std::string& first_interface_description() const;
  // Bytes consumed so far (for progress), and the file's size (0 when read from a stream).
  [[nodiscard]] std::uint64_t bytes_read() const;
  [[nodiscard]] std::uint64_t size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// True when `head` (at least the first 4 bytes of a file) starts like pcap or pcapng.
bool is_pcap_file_start(std::span<const std::uint8_t> head);

// Converts a pcapng timestamp to ns since 1970. `tsresol` as in if_tsresol (MSB clear:
// 10^-n s, set: 2^-n s); `offset_seconds` = if_tsoffset. nullopt when it does not fit.
std::optional<Nanos> pcapng_ticks_to_nanos(std::uint64_t ticks, std::uint8_t tsresol,
                                           std::int64_t offset_seconds);

}  // namespace rtu
