#pragma once
// A RecordSink that writes what the decoder found to pcapng or classic pcap for Wireshark.
//
// Interface 0 (LINKTYPE_WIRESHARK_UPPER_PDU, ns): one record per frame, dissector `mbrtu`,
// time = the frame's first byte. Requests carry ports 1 → 502 and epb_flags outbound,
// responses 502 → 1 and inbound (open with `-o mbrtu.tcp.port:502` so Wireshark classifies
// every function code). Frames with issues get a comment listing them ("crc: CRC check
// failed; ..."), and so do frames Wireshark's dissector declines (unit 0, under 5 bytes).
// Noise records (bytes that form no frame) are written there too, for dissector `data`
// with the comment "noise: ...", so every byte of the capture is in the file.
//
// Interface 1 (LINKTYPE_RTAC_SERIAL, ns), pcapng with `raw` only: every chunk as read,
// time = its read completion (for sources that measured each byte's start: that start plus
// the bytes' duration at the line rate), as DATA_RX_START; where line errors mark bytes the chunk
// is split into records of PARITY_ERROR, FRAMING_ERROR, SERIAL_BREAK_EVENT or SERIAL_OVERFLOW_EVENT
// holding those bytes, all with the chunk's time (an importer joins records with equal times back
// into one chunk). Raw and frame records are interleaved in time order.
//
// Classic pcap: interface 0 only, without comments or flags (the format has neither).
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "capture/byte_output.hpp"
#include "capture/pcap_writer.hpp"
#include "capture/pcapng_writer.hpp"
#include "capture/rtac_serial.hpp"
#include "core/chunk.hpp"
#include "framing/record.hpp"

namespace rtu {

enum class PcapExportFormat : std::uint8_t { kPcapng, kPcap };

struct PcapExportOptions {
  PcapExportFormat format = PcapExportFormat::kPcapng;
  bool raw = false;  // pcapng only
};

struct PcapExportCounts {
  std::uint64_t frames = 0;
  std::uint64_t noise = 0;
  std::uint64_t raw_records = 0;
  // pcap and pcapng cannot hold times before 1970. When the first record starts earlier (a
  // text capture whose clock starts at 0, with the first frame's transmission counted back
  // from its end), every time is shifted by this many whole seconds; a later record still
  // before 1970 is written at 0 and counted.
  Nanos shifted_by = 0;
  Nanos first_time = 0;  // the first record's time before the shift
  std::uint64_t clamped_to_zero = 0;
};

class PcapExportSink final : public RecordSink {
 public:
  PcapExportSink(std::unique_ptr<ByteOutput> output, const PcapExportOptions& options);

  void on_capture(const CaptureInfo& info) override;
  void on_record(Record& record) override;
  void on_finish() override;
  // Raw chunks, in input order, before the records they produce (ReplayOptions::on_chunk).
  void on_chunk(const Chunk& chunk);

  [[nodiscard]] const PcapExportCounts& counts() const { return counts_; }

 private:
  struct RawRecord {
    Nanos t = 0;
    RtacEvent event = RtacEvent::kDataRxStart;
    std::vector<std::uint8_t> bytes;
    std::string comment;  // the read's time marks, on its first record
  };
  void open(const CaptureInfo& info);
  void write_raw_until(Nanos t);
  void write_raw(const RawRecord& raw);
  // The time to write for `t`: shifted and clamped as PcapExportCounts says.
  Nanos file_time(Nanos t);

  std::unique_ptr<ByteOutput> pending_output_;  // until the first record decides the writer
  PcapExportOptions options_;
  std::unique_ptr<PcapngWriter> pcapng_;
  std::unique_ptr<PcapWriter> pcap_;
  std::uint32_t frames_interface_ = 0;
  std::uint32_t raw_interface_ = 0;
  Nanos char_time_ = LineSettings{}.char_time();
  std::deque<RawRecord> raw_queue_;
  std::vector<std::uint8_t> buffer_;
  std::string comment_;
  PcapExportCounts counts_;
  bool first_written_ = false;
};

// The comment for a record ("" when it needs none).
std::string export_comment(const Record& record);

}  // namespace rtu
