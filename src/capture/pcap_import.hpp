#pragma once
// Reads what rtuscope (or another tool) stored in a pcap/pcapng file, in file order:
//  * LINKTYPE_RTAC_SERIAL (250) records become timed chunks for the framer. The record's
//    time is the chunk's read completion. Consecutive records with the same time are one
//    chunk (rtuscope's raw export splits a chunk where its line errors change). Line
//    events carry their bytes flagged: PARITY_ERROR → parity, FRAMING_ERROR → framing,
//    SERIAL_BREAK_EVENT → break, SERIAL_OVERFLOW_EVENT and CAPTURE_DATA_LOST → overrun.
//    An event with no bytes flags the next byte that arrives. CAPTURE_COMPLETE (which
//    `rtuscope live` writes when it stops) becomes an end item: the time the capture ended.
//  * LINKTYPE_WIRESHARK_UPPER_PDU (252) records for dissector `mbrtu` are frames whose
//    boundaries are known; records for dissector `data` are noise (rtuscope writes the
//    bytes that form no frame that way). The record's time is the first byte's start.
//    Records are delivered whole, however long (DecodePipeline::push_frame splits a frame
//    record longer than the 256 bytes a record holds).
// Other link types, other dissectors and malformed records: InputError with the offset;
// after it next() returns false.
// Records the capturing tool cut short (snap length) are read as far as they go and
// counted (cut_records()), so the caller can say that bytes are missing.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "capture/capture_file.hpp"
#include "capture/pcap_reader.hpp"
#include "capture/upper_pdu.hpp"
#include "core/chunk.hpp"
#include "core/input_error.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

// Records whose original length exceeds what the file holds of them.
struct CutRecords {
  std::uint64_t count = 0;
  std::uint64_t first_offset = 0;  // of the first one, in the file
  std::size_t first_captured = 0;
  std::uint32_t first_original = 0;
};

// "FILE: offset N: record cut to X of its Y bytes ..." ("" when nothing was cut).
std::string cut_records_warning(const std::string& file, const CutRecords& cut);

struct PcapItem {
  enum class Kind : std::uint8_t { kChunk, kFrame, kNoise, kEnd };
  Kind kind = Kind::kChunk;
  Chunk chunk;  // kChunk; spans valid until the next call
  // kFrame / kNoise; valid until the next call
  std::span<const std::uint8_t> bytes;
  Nanos t_start = 0;         // kFrame / kNoise: first byte's start; kEnd: when the capture ended
  std::uint64_t offset = 0;  // byte offset of the (first) record in the file
  Nanos resolution = 0;      // timestamp step of its interface
};

class PcapImporter {
 public:
  explicit PcapImporter(const CaptureFile& file);
  ~PcapImporter();
  PcapImporter(const PcapImporter&) = delete;
  PcapImporter& operator=(const PcapImporter&) = delete;

  bool next(PcapItem& out);
  // Line settings from an interface description such as "RS-485 9600 8E1" (rtuscope's
  // exports write them there); known once the first item was read, or for a file without
  // packets once next() returned false.
  [[nodiscard]] std::optional<LineSettings> declared_settings() const { return declared_; }
  // Timing resolution of the capture the frames were decoded from, from an interface
  // description holding "timing resolution <ms> ms" (rtuscope's exports write it).
  [[nodiscard]] std::optional<Nanos> declared_resolution() const { return resolution_; }
  // The response timeout a live recording was decoded with, from "response timeout <ms> ms".
  [[nodiscard]] std::optional<Nanos> declared_timeout() const { return timeout_; }
  [[nodiscard]] const std::string& name() const;
  // Bytes of the file read so far and its size, for progress (see PcapReader).
  [[nodiscard]] std::uint64_t bytes_read() const;
  [[nodiscard]] std::uint64_t input_size() const;
  // Records cut short among those read so far.
  [[nodiscard]] const CutRecords& cut_records() const { return cut_; }

 private:
  bool fetch();  // next packet into packet_; false at the end
  void take_declarations(std::string_view interface_description);
  [[noreturn]] void fail(std::string message);
  std::uint8_t port_of(std::uint32_t section, std::uint32_t interface_id);
  std::unique_ptr<PcapReader> reader_;
  UpperPduReader upper_pdu_;
  CapturePacket packet_;
  bool have_packet_ = false;
  bool ended_ = false;
  std::optional<LineSettings> declared_;
  std::optional<Nanos> resolution_;
  std::optional<Nanos> timeout_;
  // The interfaces (section, id) whose descriptions were read for the above: each is read
  // once, not once per packet.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> described_;
  std::optional<std::pair<std::uint32_t, std::uint32_t>> last_interface_;  // the last packet's
  CutRecords cut_;
  std::optional<InputError> deferred_;
  std::uint8_t pending_errors_ = 0;  // from events without bytes
  std::vector<std::uint8_t> bytes_;
  std::vector<std::uint8_t> errors_;
  std::uint32_t port_section_ = 0;
  std::vector<std::uint32_t> port_interfaces_;  // index = port
  // The last read's interface and its port; no interface has this id before the first read.
  std::uint32_t last_port_interface_ = UINT32_MAX;
  std::uint8_t last_port_ = 0;
};

// "RS-485 9600 8E1; <source>; timing resolution 16 ms[; response timeout 1000 ms]": what a
// recording's interface declares of its capture, in the words the functions below read back
// (durations exactly: "0.500000 ms"). `source` names what recorded it, e.g. "rtuscope live".
std::string recording_description(const LineSettings& line, std::string_view source,
                                  Nanos resolution, std::optional<Nanos> response_timeout);
// "<key><ms> ms" anywhere in `text`, e.g. key "timing resolution " and "16.000 ms".
std::optional<Nanos> parse_milliseconds_after(std::string_view text, std::string_view key);
// "timing resolution 16.000 ms" anywhere in `text`.
std::optional<Nanos> parse_resolution_description(std::string_view text);
// "response timeout 300 ms" anywhere in `text`.
std::optional<Nanos> parse_timeout_description(std::string_view text);

// "9600 8E1" anywhere in `text` (baud, 8 data bits, parity letter, stop bits).
std::optional<LineSettings> parse_line_description(std::string_view text);

}  // namespace rtu
