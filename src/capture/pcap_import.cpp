#include "capture/pcap_import.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "capture/pcap_format.hpp"
#include "capture/rtac_serial.hpp"
#include "capture/upper_pdu.hpp"
#include "core/input_error.hpp"

namespace rtu {
namespace {

std::uint8_t errors_of(std::uint8_t event) {
  switch (static_cast<RtacEvent>(event)) {
    case RtacEvent::kParityError: return kParityError;
    case RtacEvent::kFramingError: return kFramingError;
    case RtacEvent::kSerialBreak: return kBreak;
    case RtacEvent::kSerialOverflow:
    case RtacEvent::kCaptureDataLost: return kOverrun;
    default: return kLineOk;
  }
}

// A CAPTURE_COMPLETE record without bytes: the end of a live capture. Looked at directly
// (the header's event byte): asked of every record.
bool is_capture_complete(std::span<const std::uint8_t> record) {
  return record.size() == kRtacHeaderSize &&
         static_cast<RtacEvent>(record[kRtacEventOffset]) == RtacEvent::kCaptureComplete;
}

}  // namespace

std::optional<LineSettings> parse_line_description(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (std::isdigit(static_cast<unsigned char>(text[i])) == 0) continue;
    if (i > 0 && std::isalnum(static_cast<unsigned char>(text[i - 1])) != 0) continue;
    std::size_t j = i;
    std::uint64_t baud = 0;
    while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j])) != 0 &&
           baud < 100'000'000) {
      baud = baud * 10 + static_cast<std::uint64_t>(text[j] - '0');
      ++j;
    }
    if (j + 4 > text.size() || text[j] != ' ' || text[j + 1] != '8') continue;
    const auto parity = parse_parity(text.substr(j + 2, 1));
    const char stop = text[j + 3];
    if (!parity || (stop != '1' && stop != '2') || baud == 0) continue;
    if (j + 4 < text.size() && std::isalnum(static_cast<unsigned char>(text[j + 4])) != 0) {
      continue;
    }
    LineSettings line;
    line.baud = static_cast<std::uint32_t>(baud);
    line.parity = *parity;
    line.stop_bits = static_cast<std::uint8_t>(stop - '0');
    return line;
  }
  return std::nullopt;
}

std::optional<Nanos> parse_resolution_description(std::string_view text) {
  return parse_milliseconds_after(text, "timing resolution ");
}

std::optional<Nanos> parse_timeout_description(std::string_view text) {
  return parse_milliseconds_after(text, "response timeout ");
}

namespace {

// "16 ms", "0.500000 ms": exact, and what parse_milliseconds_after reads back.
std::string milliseconds_text(Nanos t) {
  return t % kNanosPerMilli == 0
             ? fmt::format("{} ms", t / kNanosPerMilli)
             : fmt::format("{}.{:06} ms", t / kNanosPerMilli, t % kNanosPerMilli);
}

}  // namespace

std::string recording_description(const LineSettings& line, std::string_view source,
                                  Nanos resolution, std::optional<Nanos> response_timeout) {
  std::string text = fmt::format("RS-485 {}; {}; timing resolution {}", line.describe(), source,
                                 milliseconds_text(resolution));
  if (response_timeout) text += "; response timeout " + milliseconds_text(*response_timeout);
  return text;
}

std::optional<Nanos> parse_milliseconds_after(std::string_view text, std::string_view key) {
  const auto at = text.find(key);
  if (at == std::string_view::npos) return std::nullopt;
  std::size_t i = at + key.size();
  Nanos whole = 0;
  Nanos fraction = 0;
  Nanos scale = kNanosPerMilli;
  bool digits = false;
  while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])) != 0 &&
         whole < kNanosPerSecond * 1000) {
    whole = whole * 10 + (text[i++] - '0');
    digits = true;
  }
  if (i < text.size() && text[i] == '.') {
    ++i;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])) != 0) {
      if (scale > 1) {
        scale /= 10;
        fraction += (text[i] - '0') * scale;
      }
      ++i;
      digits = true;
    }
  }
  if (!digits || text.substr(i, 3) != " ms") return std::nullopt;
  return whole * kNanosPerMilli + fraction;
}

std::string cut_records_warning(const std::string& file, const CutRecords& cut) {
  if (cut.count == 0) return "";
  return fmt::format(
      "{}: offset {}: record cut to {} of its {} bytes by the capturing tool's snap length{}; "
      "the missing bytes are not in the file and cannot be decoded",
      file, cut.first_offset, cut.first_captured, cut.first_original,
      cut.count > 1 ? fmt::format(" ({} records cut)", cut.count) : "");
}

PcapImporter::PcapImporter(const CaptureFile& file)
    : reader_(std::make_unique<PcapReader>(
          file, std::vector<std::uint16_t>{pcap::kLinkTypeRtacSerial, pcap::kLinkTypeUpperPdu})) {}

PcapImporter::~PcapImporter() = default;

const std::string& PcapImporter::name() const {
  return reader_->name();
}
std::uint64_t PcapImporter::bytes_read() const {
  return reader_->bytes_read();
}
std::uint64_t PcapImporter::input_size() const {
  return reader_->size();
}

bool PcapImporter::fetch() {
  if (have_packet_) return true;
  if (ended_) return false;
  if (!reader_->next(packet_)) {
    ended_ = true;
    // A recording of a quiet line has interfaces but no packets: its line is still declared.
    if (described_.empty()) take_declarations(reader_->first_interface_description());
    return false;
  }
  // Nearly every packet is on the interface of the packet before it: that one needs no look.
  const auto interface = std::make_pair(packet_.section, packet_.interface_id);
  if (interface != last_interface_) {
    last_interface_ = interface;
    if (std::find(described_.begin(), described_.end(), interface) == described_.end()) {
      described_.push_back(interface);
      take_declarations(packet_.interface_description);
    }
  }
  if (packet_.original_length > packet_.data.size()) {
    if (cut_.count == 0) {
      cut_.first_offset = packet_.offset;
      cut_.first_captured = packet_.data.size();
      cut_.first_original = packet_.original_length;
    }
    ++cut_.count;
  }
  have_packet_ = true;
  return true;
}

void PcapImporter::take_declarations(std::string_view interface_description) {
  if (!declared_) declared_ = parse_line_description(interface_description);
  if (!resolution_) resolution_ = parse_resolution_description(interface_description);
  if (!timeout_) timeout_ = parse_timeout_description(interface_description);
}

// Receivers are numbered in the order their first read appears in the section, so a
// two-port live recording gives ports 0 and 1, and an export whose raw reads sit on a
// second interface still gives port 0.
std::uint8_t PcapImporter::port_of(std::uint32_t section, std::uint32_t interface_id) {
  // Nearly every read is on the port of the read before it: that one needs no look.
  if (section == port_section_ && interface_id == last_port_interface_) return last_port_;
  if (section != port_section_) {
    port_section_ = section;
    port_interfaces_.clear();
  }
  last_port_interface_ = interface_id;
  const auto it = std::find(port_interfaces_.begin(), port_interfaces_.end(), interface_id);
  if (it != port_interfaces_.end()) {
    last_port_ = static_cast<std::uint8_t>(it - port_interfaces_.begin());
  } else if (port_interfaces_.size() == UINT8_MAX) {
    last_port_ = UINT8_MAX;
  } else {
    port_interfaces_.push_back(interface_id);
    last_port_ = static_cast<std::uint8_t>(port_interfaces_.size() - 1);
  }
  return last_port_;
}

// The reader stops at the first damage, as PcapReader does: reading on would deliver what
// follows a record nobody could place, and the caller's error would be followed by more.
void PcapImporter::fail(std::string message) {
  ended_ = true;
  have_packet_ = false;
  throw InputError(std::move(message));
}

bool PcapImporter::next(PcapItem& out) {
  for (;;) {
    // Checked on every turn: a read of events without bytes may end at the damage too.
    if (deferred_) {
      const InputError error = *deferred_;
      deferred_.reset();
      ended_ = true;
      throw error;
    }
    if (!fetch()) return false;
    const std::uint64_t at = packet_.offset;
    std::string error;
    if (packet_.link_type == pcap::kLinkTypeUpperPdu) {
      have_packet_ = false;
      UpperPdu pdu;
      if (!upper_pdu_.parse(packet_.data, pdu, error)) {
        fail(fmt::format("{}: offset {}: upper-PDU record: {}", name(), at, error));
      }
      if (pdu.dissector != upper_pdu::kModbusRtuDissector && pdu.dissector != "data") {
        fail(fmt::format(
            "{}: offset {}: upper-PDU record for dissector '{}'; expected 'mbrtu' (Modbus RTU "
            "frames) or 'data' (bytes that form no frame)",
            name(), at, pdu.dissector));
      }
      // Wireshark writes records whose PDU is empty; they hold no byte, so no frame or
      // noise (a 0-byte "frame" would be a request of slave 0 that nobody answers).
      if (pdu.payload.empty()) continue;
      out = PcapItem{};
      out.kind = pdu.dissector == "data" ? PcapItem::Kind::kNoise : PcapItem::Kind::kFrame;
      out.bytes = pdu.payload;  // in the reader's block, which stays until the next call
      out.t_start = packet_.t;
      out.offset = at;
      out.resolution = packet_.resolution;
      return true;
    }
    if (is_capture_complete(packet_.data)) {
      have_packet_ = false;
      out = PcapItem{};
      out.kind = PcapItem::Kind::kEnd;
      out.t_start = packet_.t;
      out.offset = at;
      out.resolution = packet_.resolution;
      return true;
    }
    // RTAC serial: gather the records that share this time into one chunk.
    const Nanos t = packet_.t;
    const std::uint32_t interface_id = packet_.interface_id;
    const std::uint32_t section = packet_.section;
    // Each field set (no reset of the whole item first: this runs at every read). A field
    // added to PcapItem or Chunk must be set here too; the sizes checked make one visible.
    static_assert(sizeof(PcapItem) == 120 && sizeof(Chunk) == 72,
                  "set every field of a chunk item below");
    out.kind = PcapItem::Kind::kChunk;
    out.chunk.t_first_start = kUnknownTime;
    out.chunk.errors = {};
    out.chunk.port = port_of(section, interface_id);
    out.chunk.time_clamped = false;  // as the file's comment says; the reader's clamp too
    out.chunk.read_late = false;
    out.chunk.quiet_until = kUnknownTime;
    out.bytes = {};
    out.t_start = 0;
    out.offset = at;
    out.resolution = packet_.resolution;
    bytes_.clear();
    errors_.clear();
    bool any_error = false;
    while (have_packet_ && packet_.link_type == pcap::kLinkTypeRtacSerial && packet_.t == t &&
           packet_.interface_id == interface_id && packet_.section == section &&
           !is_capture_complete(packet_.data)) {
      const auto rec = parse_rtac_record(packet_.data, error);
      if (!rec) fail(fmt::format("{}: offset {}: {}", name(), packet_.offset, error));
      const std::uint8_t flags = errors_of(rec->event);
      if (!packet_.comment.empty()) {
        const ReadTimeMarks marks = time_marks_of(packet_.comment);
        out.chunk.read_late = out.chunk.read_late || marks.read_late;
        if (marks.quiet_before != kUnknownTime) out.chunk.quiet_until = t - marks.quiet_before;
        out.chunk.time_clamped = out.chunk.time_clamped || marks.time_clamped;
      }
      if (rec->payload.empty()) {
        pending_errors_ = static_cast<std::uint8_t>(pending_errors_ | flags);
      } else {
        // The first byte also takes the errors of the events before it. Error flags are
        // kept only once a byte has one (clean reads, nearly all of them, need none).
        const auto first = static_cast<std::uint8_t>(flags | pending_errors_);
        pending_errors_ = 0;
        if (first != 0 || flags != 0) {
          any_error = true;
          errors_.resize(bytes_.size(), kLineOk);
          errors_.push_back(first);
          errors_.resize(bytes_.size() + rec->payload.size(), flags);
        }
        bytes_.insert(bytes_.end(), rec->payload.begin(), rec->payload.end());
      }
      have_packet_ = false;
      try {
        if (!fetch()) break;
      } catch (const InputError& e) {
        // Deliver the bytes gathered so far first; the error comes with the next call.
        deferred_ = e;
        break;
      }
    }
    if (bytes_.empty()) continue;  // events with no bytes: carried to the next byte
    out.chunk.t_end = t;
    out.chunk.bytes = bytes_;
    if (any_error) {
      errors_.resize(bytes_.size(), kLineOk);
      out.chunk.errors = errors_;
    }
    out.chunk.origin = at;
    return true;
  }
}

}  // namespace rtu
