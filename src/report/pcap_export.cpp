#include "report/pcap_export.hpp"

#include <fmt/format.h>

#include "capture/pcap_format.hpp"
#include "capture/upper_pdu.hpp"

namespace rtu {
namespace {

// Bound on raw records held back for time order (frames lag chunks by a few records).
constexpr std::size_t kMaxRawQueue = 4096;

RtacEvent event_for(std::uint8_t errors) {
  if ((errors & kBreak) != 0) return RtacEvent::kSerialBreak;
  if ((errors & kOverrun) != 0) return RtacEvent::kSerialOverflow;
  if ((errors & kFramingError) != 0) return RtacEvent::kFramingError;
  if ((errors & kParityError) != 0) return RtacEvent::kParityError;
  return RtacEvent::kDataRxStart;
}

}  // namespace

std::string export_comment(const Record& record) {
  std::string text;
  const auto add = [&](std::string_view part) {
    if (!text.empty()) text += "; ";
    text += part;
  };
  if (record.kind == RecordKind::kFrame) {
    if (record.size > 0 && record.slave() == 0) {
      add("broadcast (unit 0): Wireshark's Modbus RTU dissector does not decode it");
    } else if (record.size < 5) {
      add(fmt::format("{}-byte frame: Wireshark's Modbus RTU dissector needs at least 5",
                      record.size));
    }
  }
  record.issues.for_each([&](IssueId id) {
    const IssueInfo& info = issue_info(id);
    add(fmt::format("{}: {}", info.key, info.summary));
  });
  return text;
}

PcapExportSink::PcapExportSink(std::unique_ptr<ByteOutput> output, const PcapExportOptions& options)
    : pending_output_(std::move(output)), options_(options) {}

void PcapExportSink::open(const CaptureInfo& info) {
  if (pcapng_ || pcap_) return;
  if (options_.format == PcapExportFormat::kPcap) {
    pcap_ = std::make_unique<PcapWriter>(std::move(pending_output_), pcap::kLinkTypeUpperPdu,
                                         PcapResolution::kNanos);
    return;
  }
  pcapng_ = std::make_unique<PcapngWriter>(std::move(pending_output_));
  const std::string line = fmt::format("{}, timing resolution {:.3f} ms", info.line.describe(),
                                       to_millis(info.timing_resolution));
  frames_interface_ = pcapng_->add_interface(
      {pcap::kLinkTypeUpperPdu, info.source, fmt::format("Modbus RTU frames, {}", line), 9, 0});
  if (options_.raw) {
    raw_interface_ = pcapng_->add_interface(
        {pcap::kLinkTypeRtacSerial, info.source, fmt::format("raw serial reads, {}", line), 9, 0});
  }
}

void PcapExportSink::on_capture(const CaptureInfo& info) {
  open(info);
}

void PcapExportSink::on_chunk(const Chunk& chunk) {
  if (!options_.raw || chunk.bytes.empty()) return;
  std::size_t start = 0;
  // A read's time marks go with its first record, so a decode of the export frames it the
  // same way (rtac_serial.hpp).
  // RTAC records carry one time; a reader counts the bytes back from it. Where the source
  // measured the first byte's start (logic analysers), the time is where its bytes end at
  // the line rate, so the framer places every byte as measured.
  const Nanos t = chunk.t_first_start != kUnknownTime
                      ? chunk.t_first_start + static_cast<Nanos>(chunk.bytes.size()) * char_time_
                      : chunk.t_end;
  std::string comment = time_marks_comment(time_marks_of(chunk, t));
  while (start < chunk.bytes.size()) {
    const std::uint8_t errors = chunk.errors.empty() ? 0 : chunk.errors[start];
    std::size_t end = start + 1;
    while (end < chunk.bytes.size() && (chunk.errors.empty() ? 0 : chunk.errors[end]) == errors) {
      ++end;
    }
    RawRecord raw;
    raw.t = t;
    raw.event = event_for(errors);
    raw.bytes.assign(chunk.bytes.begin() + static_cast<std::ptrdiff_t>(start),
                     chunk.bytes.begin() + static_cast<std::ptrdiff_t>(end));
    raw.comment = comment;
    comment = {};
    raw_queue_.push_back(std::move(raw));
    start = end;
  }
  while (raw_queue_.size() > kMaxRawQueue) {
    write_raw(raw_queue_.front());
    raw_queue_.pop_front();
  }
}

void PcapExportSink::write_raw_until(Nanos t) {
  while (!raw_queue_.empty() && raw_queue_.front().t <= t) {
    write_raw(raw_queue_.front());
    raw_queue_.pop_front();
  }
}

Nanos PcapExportSink::file_time(Nanos t) {
  if (!first_written_) {
    first_written_ = true;
    counts_.first_time = t;
    if (t < 0) {
      const Nanos seconds = (-t + kNanosPerSecond - 1) / kNanosPerSecond;
      counts_.shifted_by = seconds * kNanosPerSecond;
    }
  }
  t += counts_.shifted_by;
  if (t < 0) {
    ++counts_.clamped_to_zero;
    return 0;
  }
  return t;
}

void PcapExportSink::write_raw(const RawRecord& raw) {
  if (!pcapng_) open(CaptureInfo{});
  const Nanos t = file_time(raw.t);
  build_rtac_record(t, raw.event, 0, raw.bytes, buffer_);
  PcapngPacketMeta meta;
  meta.comment = raw.comment;
  pcapng_->write_packet(raw_interface_, t, buffer_, meta);
  ++counts_.raw_records;
}

void PcapExportSink::on_record(Record& record) {
  if (!pcapng_ && !pcap_) open(CaptureInfo{});
  write_raw_until(record.t_start);
  const bool frame = record.kind == RecordKind::kFrame;
  UpperPduBuild build;
  build.dissector = frame ? upper_pdu::kModbusRtuDissector : std::string_view("data");
  build.direction = record.role == Role::kRequest    ? PduDirection::kRequest
                    : record.role == Role::kResponse ? PduDirection::kResponse
                                                     : PduDirection::kUnknown;
  if (!frame) {
    build.protocol_column = "RTU noise";
  } else if (mbrtu_declines(record.bytes())) {
    build.protocol_column = "Modbus RTU";
  }
  build_upper_pdu(record.bytes(), build, buffer_);
  if (frame) {
    ++counts_.frames;
  } else {
    ++counts_.noise;
  }
  const Nanos t = file_time(record.t_start);
  if (pcap_) {
    pcap_->write_packet(t, buffer_);
    return;
  }
  comment_ = export_comment(record);
  PcapngPacketMeta meta;
  meta.comment = comment_;
  meta.flags = build.direction == PduDirection::kRequest    ? pcap::kFlagsOutbound
               : build.direction == PduDirection::kResponse ? pcap::kFlagsInbound
                                                            : 0;
  pcapng_->write_packet(frames_interface_, t, buffer_, meta);
}

void PcapExportSink::on_finish() {
  if (!pcapng_ && !pcap_) open(CaptureInfo{});
  write_raw_until(std::numeric_limits<Nanos>::max());
  if (pcapng_) pcapng_->flush();
  if (pcap_) pcap_->flush();
}

}  // namespace rtu
