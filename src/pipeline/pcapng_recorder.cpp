#include "pipeline/pcapng_recorder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <utility>
#include <vector>

#include "capture/byte_output.hpp"
#include "capture/capture_set_gaps.hpp"
#include "capture/pcap_format.hpp"
#include "capture/pcap_import.hpp"
#include "core/input_error.hpp"
#include "core/output_error.hpp"

namespace rtu {
namespace {

RtacEvent event_for(std::uint8_t errors, RtacEvent data_event) {
  if ((errors & kBreak) != 0) return RtacEvent::kSerialBreak;
  if ((errors & kOverrun) != 0) return RtacEvent::kSerialOverflow;
  if ((errors & kFramingError) != 0) return RtacEvent::kFramingError;
  if ((errors & kParityError) != 0) return RtacEvent::kParityError;
  return data_event;
}

// Block overhead of an EPB without options, for the size limit (an estimate is enough).
constexpr std::uint64_t kRecordOverhead = 32 + kRtacHeaderSize + 3;

bool rotating(const RotationPolicy& rotation) {
  return rotation.max_bytes != 0 || rotation.max_age != 0;
}

// The files of the rotation set at `path` (<stem>-N<ext> beside it) that exist already, by
// number: a recorder started again (a restart after a power cut, the same command run once
// more) goes on after the highest, where starting at 0001 again wrote over the first files
// of the set and left it mixed with the ones after them.
std::vector<std::pair<std::uint64_t, std::string>> existing_set_files(const std::string& path) {
  const std::filesystem::path p(path);
  const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : ".";
  const std::string stem = (p.parent_path() / p.stem()).string();
  std::vector<std::pair<std::uint64_t, std::string>> found;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    // Named as beside `path` (not as the folder's listing spells it), so the stems compare.
    const std::string file = (p.parent_path() / it->path().filename()).string();
    const auto name = parse_rotation_name(file);
    if (name && name->stem == stem && name->extension == p.extension().string() &&
        name->digits >= 4) {
      found.emplace_back(name->number, file);
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace

RotationPolicy parse_rotation(const std::string& text) {
  std::size_t digits = 0;
  while (digits < text.size() && std::isdigit(static_cast<unsigned char>(text[digits])) != 0) {
    ++digits;
  }
  std::string unit = text.substr(digits);
  for (auto& c : unit) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  RotationPolicy policy;
  if (digits > 0 && digits <= 12) {
    const std::uint64_t n = std::stoull(text.substr(0, digits));
    if (unit == "b") policy.max_bytes = n;
    if (unit == "kb" || unit == "k") policy.max_bytes = n * 1000;
    if (unit == "mb") policy.max_bytes = n * 1000 * 1000;
    if (unit == "gb") policy.max_bytes = n * 1000 * 1000 * 1000;
    if (unit == "s") policy.max_age = static_cast<Nanos>(n) * kNanosPerSecond;
    if (unit == "m" || unit == "min") policy.max_age = static_cast<Nanos>(n) * 60 * kNanosPerSecond;
    if (unit == "h") policy.max_age = static_cast<Nanos>(n) * 3600 * kNanosPerSecond;
    if (unit == "d") policy.max_age = static_cast<Nanos>(n) * 86400 * kNanosPerSecond;
  }
  if ((policy.max_bytes == 0 && policy.max_age == 0)) {
    throw InputError(fmt::format(
        "--rotate: expected a size (e.g. 100MB, 2GB) or a duration (e.g. 30m, 1h, 1d), found '{}'",
        text));
  }
  return policy;
}

PcapngRecorder::PcapngRecorder(std::string path, RotationPolicy rotation)
    : path_(std::move(path)), rotation_(rotation) {
  if (!rotating(rotation_)) return;
  // The set's files from before count towards `keep` as this run's own do.
  for (auto& [number, file] : existing_set_files(path_)) {
    file_index_ = number;
    kept_files_.push_back(std::move(file));
  }
}

PcapngRecorder::PcapngRecorder(std::unique_ptr<ByteOutput> output, std::string name)
    : path_(std::move(name)), given_output_(std::move(output)) {}

PcapngRecorder::~PcapngRecorder() {
  try {
    if (writer_) writer_->flush();
  } catch (const OutputError&) {
    // Said already, or too late to say: the file keeps its whole blocks either way.
  }
}

void PcapngRecorder::stop_recording(const std::string& why) {
  if (!failure_.empty()) return;
  failure_ = why;
  if (failure_listener_) failure_listener_(failure_);
}

void PcapngRecorder::add_port(std::size_t port, const std::string& name, const LineSettings& line,
                              const SerialStatus& status, Nanos response_timeout) {
  if (ports_.size() <= port) ports_.resize(port + 1);
  ports_[port].name = name;
  ports_[port].description =
      recording_description(line, "rtuscope live", status.resolution, response_timeout);
  if (!bus_name_.empty()) ports_[port].description += fmt::format("; bus {}", bus_name_);
  if (writer_) {
    // A port added late (never happens in LiveCapture, which adds all first).
    interfaces_.resize(ports_.size());
    interfaces_[port] = writer_->add_interface(
        {pcap::kLinkTypeRtacSerial, ports_[port].name, ports_[port].description, 9, 0});
  }
}

void PcapngRecorder::open_file(Nanos t, bool append) {
  std::string path = path_;
  if (rotating(rotation_)) {
    const std::filesystem::path p(path_);
    path = (p.parent_path() /
            fmt::format("{}-{:04}{}", p.stem().string(), ++file_index_, p.extension().string()))
               .string();
  }
  if (writer_) writer_->flush();
  writer_ = std::make_unique<PcapngWriter>(
      given_output_ ? std::move(given_output_) : std::make_unique<FileOutput>(path, append));
  interfaces_.clear();
  for (const auto& port : ports_) {
    interfaces_.push_back(
        writer_->add_interface({pcap::kLinkTypeRtacSerial, port.name, port.description, 9, 0}));
  }
  file_bytes_ = 0;
  file_started_ = t;
  if (!append || all_files_.empty() || all_files_.back() != path) {
    all_files_.push_back(path);
    kept_files_.push_back(path);
  }
  while (rotation_.keep != 0 && kept_files_.size() > rotation_.keep) {
    std::error_code ec;
    std::filesystem::remove(kept_files_.front(), ec);
    kept_files_.pop_front();
  }
  if (file_listener_) file_listener_(path, t);
}

void PcapngRecorder::reopen(Nanos t) {
  ++reopens_;
  if (!writer_ || !failure_.empty()) return;  // the first read opens the file anyway
  open_file(t, !rotating(rotation_));
}

void PcapngRecorder::add_comment(Nanos t, std::string_view text) {
  if (ports_.empty() || !failure_.empty()) return;
  try {
    write(0, t, RtacEvent::kStatusChange, {}, text);
  } catch (const OutputError& e) {
    stop_recording(e.what());
  }
}

void PcapngRecorder::maybe_rotate(Nanos t) {
  if (!writer_) {
    open_file(t);
    return;
  }
  if (file_started_ == kUnknownTime) file_started_ = t;
  const bool too_big = rotation_.max_bytes != 0 && file_bytes_ >= rotation_.max_bytes;
  const bool too_old = rotation_.max_age != 0 && t - file_started_ >= rotation_.max_age;
  if (too_big || too_old) open_file(t);
}

void PcapngRecorder::write(std::size_t port, Nanos t, RtacEvent event,
                           std::span<const std::uint8_t> bytes, std::string_view comment) {
  if (!writer_) open_file(t);
  build_rtac_record(t, event, 0, bytes, buffer_);
  PcapngPacketMeta meta;
  meta.comment = comment;
  if (ports_.size() == 2) meta.flags = port == 0 ? pcap::kFlagsOutbound : pcap::kFlagsInbound;
  writer_->write_packet(interfaces_.at(port), t, buffer_, meta);
  file_bytes_ += kRecordOverhead + buffer_.size() + comment.size();
  bytes_written_ += kRecordOverhead + buffer_.size() + comment.size();
  ++records_;
}

void PcapngRecorder::on_chunk(std::size_t port, const Chunk& chunk) {
  if (!failure_.empty()) {
    ++unrecorded_reads_;
    return;
  }
  try {
    record_chunk(port, chunk);
  } catch (const OutputError& e) {
    ++unrecorded_reads_;
    stop_recording(e.what());
  } catch (const InputError& e) {
    // A new file of a rotation that cannot be created (the disk is full).
    ++unrecorded_reads_;
    stop_recording(e.what());
  }
}

void PcapngRecorder::record_chunk(std::size_t port, const Chunk& chunk) {
  const RtacEvent data_event =
      ports_.size() == 2 && port == 0 ? RtacEvent::kDataTxStart : RtacEvent::kDataRxStart;
  // A new file starts only before a whole read: the records of one read (split where its
  // line errors change) are joined again by their common time only within one file, and a
  // lost-data event flags the next byte read only when that byte is in the same file.
  if (!event_waits_for_byte_) maybe_rotate(chunk.t_end);
  event_waits_for_byte_ = false;
  // A late read says so on its first record (a replay takes the mark back from it).
  std::string comment = time_marks_comment(time_marks_of(chunk, chunk.t_end));
  if (chunk.errors.empty()) {
    write(port, chunk.t_end, data_event, chunk.bytes, comment);
    return;
  }
  std::size_t start = 0;
  while (start < chunk.bytes.size()) {
    const std::uint8_t flags = chunk.errors[start];
    std::size_t end = start + 1;
    while (end < chunk.bytes.size() && chunk.errors[end] == flags) ++end;
    write(port, chunk.t_end, event_for(flags, data_event), chunk.bytes.subspan(start, end - start),
          comment);
    comment = {};
    start = end;
  }
}

void PcapngRecorder::on_gap(std::size_t port, Nanos t, const std::string& reason) {
  if (!failure_.empty()) return;
  try {
    maybe_rotate(t);
    write(port, t, RtacEvent::kCaptureDataLost, {}, reason);
    event_waits_for_byte_ = true;
  } catch (const OutputError& e) {
    stop_recording(e.what());
  } catch (const InputError& e) {
    stop_recording(e.what());
  }
}

// The end goes into the file that holds the last reads, never alone into a new one.
void PcapngRecorder::on_end(Nanos t) {
  if (!failure_.empty()) return;
  try {
    write(0, t, RtacEvent::kCaptureComplete, {}, "capture stopped");
    writer_->flush();
  } catch (const OutputError& e) {
    stop_recording(e.what());
  }
}

void PcapngRecorder::flush() {
  if (!writer_) open_file(kUnknownTime);  // the file exists from the start
  if (!failure_.empty()) return;
  try {
    writer_->flush();
  } catch (const OutputError& e) {
    stop_recording(e.what());
  }
}

}  // namespace rtu
