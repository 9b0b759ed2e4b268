#pragma once
// Records a live capture as pcapng, chunk by chunk, exactly as read (FORMATS §2, §4):
//  * one LINKTYPE_RTAC_SERIAL (250) interface per port, ns timestamps, if_name = the port,
//    if_description = "RS-485 <baud> 8<parity><stop>; rtuscope live; timing resolution <r>;
//    response timeout <t>[; bus <name>]" (what a replay needs to decode it the same way, and
//    which bus it is);
//  * every read as DATA_RX_START (with two ports: the first as DATA_TX_START, epb_flags
//    outbound, the second as DATA_RX_START, inbound), time = its read completion; where
//    line errors mark bytes, the read is split into PARITY_ERROR / FRAMING_ERROR /
//    SERIAL_BREAK_EVENT / SERIAL_OVERFLOW_EVENT records holding those bytes, all with the
//    read's time (importers join records of equal time back into one chunk); a read the
//    host made late (Chunk::read_late) has kReadLateComment on its first record;
//  * a port that failed: CAPTURE_DATA_LOST with the reason as comment, at the failure time;
//  * the end of the capture: CAPTURE_COMPLETE at the stop time, so a replay decides what
//    was still pending (a request waiting for its answer) exactly as the live run did.
// Every record is handed to the file as a whole block and flushed at least every second by
// LiveCapture, so `kill -9` loses at most the last second and leaves a readable file.
//
// Rotation: with a size or age limit, files are named <stem>-0001<ext>, -0002, ...; each
// holds its own header and interfaces; only the newest `keep` files are kept (0 = all).
// Where files of the set exist already (a recorder started again), numbering goes on after
// the highest of them, and they count towards `keep`: nothing recorded before is written
// over, and the set stays in time order.
// A new file starts only before a whole read (never between the records of one read, nor
// between a lost-data event and the byte it flags), so the files read in time order as one
// set (capture/capture_set_reader.hpp) decode exactly as one file would.
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "capture/pcapng_writer.hpp"
#include "capture/rtac_serial.hpp"
#include "pipeline/live_capture.hpp"

namespace rtu {

struct RotationPolicy {
  std::uint64_t max_bytes = 0;  // 0 = no size limit
  Nanos max_age = 0;            // 0 = no age limit (capture time)
  std::size_t keep = 0;         // 0 = keep every file
};

// "100MB", "2GB", "500kB", "1h", "30m", "90s", "1d" → a policy (keep left at 0).
// Throws InputError naming the option when the text is neither.
RotationPolicy parse_rotation(const std::string& text);

// SIGHUP (reopen()): for external log rotation, the recording goes on in a new file at the
// same path: the file is opened again in append mode and a new pcapng section (header and
// interfaces) starts, so a file that was not moved away stays one valid capture. With
// --rotate, reopen() starts the next numbered file instead.
//
// A write that fails once the recording runs (a full disk) stops the recording, not the
// run: the file keeps every whole block written before (FileOutput cuts it back), the
// failure listener is told once, and later reads are counted, not written. A file that
// cannot be created at the start is an InputError, as a bad path is.
//
// Comments (add_comment()) are STATUS_CHANGE records without bytes carrying a pcapng
// comment: Wireshark shows them, and replays skip them (no bytes, no error flags).
class PcapngRecorder final : public ChunkRecorder {
 public:
  // Told each time a file starts (the first one included): its path and capture time.
  using FileListener = std::function<void(const std::string& path, Nanos t)>;
  // Told once when the recording stops on a write error: the message names the file and
  // says what it keeps.
  using FailureListener = std::function<void(const std::string& message)>;

  // Throws InputError when the file cannot be created.
  PcapngRecorder(std::string path, RotationPolicy rotation = {});
  // Records into `output` (a pipe to a live reader), named `name` in files(); no rotation.
  PcapngRecorder(std::unique_ptr<ByteOutput> output, std::string name);
  ~PcapngRecorder() override;

  // The bus's name (live --bus-name), added to every interface description added after it
  // ("...; bus boiler-room"), so a recording says which bus it is.
  void set_bus_name(std::string name) { bus_name_ = std::move(name); }
  void add_port(std::size_t port, const std::string& name, const LineSettings& line,
                const SerialStatus& status, Nanos response_timeout) override;
  void on_chunk(std::size_t port, const Chunk& chunk) override;
  void on_gap(std::size_t port, Nanos t, const std::string& reason) override;
  void on_end(Nanos t) override;
  void flush() override;

  // Starts a new file (see above) at capture time `t`; throws InputError when it cannot.
  void reopen(Nanos t);
  // A comment in the capture at `t` (health summaries), on the first port's interface.
  void add_comment(Nanos t, std::string_view text);
  void set_file_listener(FileListener listener) { file_listener_ = std::move(listener); }
  void set_failure_listener(FailureListener listener) { failure_listener_ = std::move(listener); }

  // Why the recording stopped ("" while it runs), and the reads not recorded since.
  [[nodiscard]] const std::string& failure() const { return failure_; }
  [[nodiscard]] std::uint64_t unrecorded_reads() const { return unrecorded_reads_; }

  [[nodiscard]] std::uint64_t records() const { return records_; }
  [[nodiscard]] std::uint64_t reopens() const { return reopens_; }
  [[nodiscard]] const std::vector<std::string>& files() const { return all_files_; }
  // Bytes written so far, every file together.
  [[nodiscard]] std::uint64_t bytes_written() const { return bytes_written_; }

 private:
  struct PortInfo {
    std::string name;
    std::string description;
  };
  void open_file(Nanos t, bool append = false);
  void maybe_rotate(Nanos t);
  void write(std::size_t port, Nanos t, RtacEvent event, std::span<const std::uint8_t> bytes,
             std::string_view comment);
  void record_chunk(std::size_t port, const Chunk& chunk);
  void stop_recording(const std::string& why);

  std::string path_;
  RotationPolicy rotation_;
  std::string bus_name_;
  std::vector<PortInfo> ports_;
  std::unique_ptr<PcapngWriter> writer_;
  std::unique_ptr<ByteOutput> given_output_;  // used instead of a file at path_, once
  std::vector<std::uint32_t> interfaces_;
  std::vector<std::uint8_t> buffer_;
  std::deque<std::string> kept_files_;
  std::vector<std::string> all_files_;
  std::uint64_t file_bytes_ = 0;
  std::uint64_t bytes_written_ = 0;
  std::uint64_t reopens_ = 0;
  FileListener file_listener_;
  FailureListener failure_listener_;
  std::string failure_;
  std::uint64_t unrecorded_reads_ = 0;
  Nanos file_started_ = kUnknownTime;
  std::uint64_t file_index_ = 0;
  std::uint64_t records_ = 0;
  bool event_waits_for_byte_ = false;  // a lost-data event flags the next byte read
};

}  // namespace rtu
