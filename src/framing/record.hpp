#pragma once
// What the framer emits: a frame (bytes that Modbus framing explains) or a noise record
// (bytes that it does not). Every input byte ends up in exactly one record. Records own
// their bytes in fixed storage, so nothing on the per-byte path allocates.
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>

#include "core/issue.hpp"
#include "core/time.hpp"
#include "framing/capture_info.hpp"

namespace rtu {

namespace dissect {
struct DeviceReading;  // what the device stage adds; declared only, so no include runs upward
}
struct FramePdu;  // the tracker's decoding of a frame (modbus/pdu.hpp); declared only, likewise

inline constexpr std::size_t kMaxAdu = 256;  // MODBUS over Serial Line §2.5.1
inline constexpr std::size_t kMinAdu = 4;    // address + function + CRC

enum class Role : std::uint8_t { kUnknown, kRequest, kResponse };

// Shapes a frame's length fits, as found by the framer (bit mask of these).
enum ShapeFit : std::uint8_t {
  kFitsNone = 0,
  kFitsRequest = 1U << 0U,
  kFitsResponse = 1U << 1U,
};

enum class RecordKind : std::uint8_t { kFrame, kNoise };

struct Record {
  RecordKind kind = RecordKind::kFrame;
  std::uint64_t seq = 0;  // position in output order, from 0
  Nanos t_start = 0;      // start of the first byte (best estimate)
  Nanos t_end = 0;        // end of the last byte
  // Silence between the previous record's last byte and this one's first byte, when the
  // timestamps show it; kUnknownTime when timing is blurred (USB batching).
  Nanos gap_before = kUnknownTime;
  std::uint64_t origin = 0;  // input line / offset of the first byte (for messages)
  std::array<std::uint8_t, kMaxAdu> storage{};
  std::uint16_t size = 0;
  std::uint8_t line_errors = 0;  // LineError bits seen on its bytes
  std::uint8_t shape_fit = kFitsNone;
  bool crc_ok = false;
  IssueSet issues;

  // Filled by the transaction tracker.
  Role role = Role::kUnknown;
  std::int64_t txn = -1;         // shared by a request and its response; -1 = none
  Nanos latency = kUnknownTime;  // response only: request end → response start
  // For a response: its request, valid only during RecordSink::on_record. Else null.
  const Record* request = nullptr;
  // The frame decoded as its role, where the tracker decoded it (CRC valid, role decided),
  // valid only during RecordSink::on_record; else null, and a stage that needs the decoding
  // makes it (decode_pdu). It is what decode_pdu(*this, role) gives, made once.
  const FramePdu* pdu = nullptr;

  // Filled by the device stage (dissect/device_stage.hpp) for the sinks after it, valid only
  // during their on_record: the slave's map, the decoded points, values. Null for noise and
  // where no device stage runs.
  const dissect::DeviceReading* device = nullptr;

  // Every field back to its default, except that storage keeps its old bytes: a producer
  // about to write `size` bytes into it need not clear all kMaxAdu of them for each frame.
  // Only bytes() (the first `size`) have meaning.
  void reset_keeping_storage() {
    kind = RecordKind::kFrame;
    seq = 0;
    t_start = 0;
    t_end = 0;
    gap_before = kUnknownTime;
    origin = 0;
    size = 0;
    line_errors = 0;
    shape_fit = kFitsNone;
    crc_ok = false;
    issues = IssueSet{};
    role = Role::kUnknown;
    txn = -1;
    latency = kUnknownTime;
    request = nullptr;
    pdu = nullptr;
    device = nullptr;
  }

  // Every field of `other`, and of its storage only the bytes in use (a record handed to
  // another thread: copying all kMaxAdu bytes of a short frame would cost most of the copy).
  void copy_in_use(const Record& other) {
    kind = other.kind;
    seq = other.seq;
    t_start = other.t_start;
    t_end = other.t_end;
    gap_before = other.gap_before;
    origin = other.origin;
    size = other.size;
    std::copy_n(other.storage.begin(), other.size, storage.begin());
    line_errors = other.line_errors;
    shape_fit = other.shape_fit;
    crc_ok = other.crc_ok;
    issues = other.issues;
    role = other.role;
    txn = other.txn;
    latency = other.latency;
    request = other.request;
    pdu = nullptr;  // it may view the other record's bytes: a holder sets its own
    device = other.device;
  }

  [[nodiscard]] std::span<const std::uint8_t> bytes() const { return {storage.data(), size}; }
  [[nodiscard]] std::uint8_t slave() const { return size > 0 ? storage[0] : 0; }
  [[nodiscard]] std::uint8_t function() const { return size > 1 ? storage[1] : 0; }
  [[nodiscard]] bool is_exception() const { return size > 1 && (storage[1] & 0x80U) != 0; }
};

// A field added to Record must be reset by reset_keeping_storage() and copied by copy_in_use()
// too: this fails until the size below is updated, as a reminder.
static_assert(sizeof(Record) == 368,
              "new Record field: reset it in reset_keeping_storage(), copy it in copy_in_use()");

// Receives records in time order.
class RecordSink {
 public:
  virtual ~RecordSink() = default;
  // Called once, before the first record.
  virtual void on_capture(const CaptureInfo& info) { (void)info; }
  virtual void on_record(Record& record) = 0;
  virtual void on_finish() {}
};

}  // namespace rtu
