// Fuzz target for the PDU decoder: decode, check, JSON and summary of one frame, optionally
// as the response to a request frame.
//
// Input layout (also what the seeds in captures/regressions/fuzz/pdu_decode/ hold):
//   byte 0        mode: 0 request, 1 response, 2 unknown role, 3 response with its request
//   mode 3 only:  byte 1 = request length L, then L request bytes
//   the rest      the frame (address, function, data, CRC as on the wire), cut at 256 bytes
//
// Besides the sanitizers, it checks what must hold for every input: the JSON object is
// well-formed UTF-8 JSON, the summary is valid UTF-8, decoding is deterministic, and every
// view the decoder returns lies inside the frame.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <span>
#include <string_view>
#include <type_traits>
#include <variant>

#if __has_include(<sanitizer/asan_interface.h>)
#include <sanitizer/asan_interface.h>
#endif
#ifndef ASAN_POISON_MEMORY_REGION
#define ASAN_POISON_MEMORY_REGION(addr, size) ((void)(addr), (void)(size))
#define ASAN_UNPOISON_MEMORY_REGION(addr, size) ((void)(addr), (void)(size))
#endif

#include "core/json_writer.hpp"
#include "modbus/pdu.hpp"

namespace {

using rtu::DecodedPdu;
using rtu::Record;
using rtu::Role;

[[noreturn]] void fail(const char* what, std::string_view detail) {
  std::fprintf(stderr, "fuzz_pdu_decode: %s: %.*s\n", what, static_cast<int>(detail.size()),
               detail.data());
  std::abort();
}

Record make_record(std::span<const std::uint8_t> bytes) {
  Record r;
  const std::size_t n = std::min(bytes.size(), r.storage.size());
  std::copy_n(bytes.begin(), n, r.storage.begin());
  r.size = static_cast<std::uint16_t>(n);
  return r;
}

// Under ASan, the unused tail of a Record's storage is poisoned while the decoder runs, so a
// read past the frame (but inside the fixed storage) is caught too. ASan works in 8-byte
// granules: up to 7 bytes right after the frame may stay readable.
class PoisonTail {
 public:
  explicit PoisonTail(const Record& r)
      : tail_(r.storage.data() + r.size), size_(r.storage.size() - r.size) {
    ASAN_POISON_MEMORY_REGION(tail_, size_);
  }
  ~PoisonTail() { ASAN_UNPOISON_MEMORY_REGION(tail_, size_); }
  PoisonTail(const PoisonTail&) = delete;
  PoisonTail& operator=(const PoisonTail&) = delete;

 private:
  const std::uint8_t* tail_;
  std::size_t size_;
};

bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t extra = 0;
    if (c < 0x80) {
      extra = 0;
    } else if ((c & 0xE0U) == 0xC0U && c >= 0xC2U) {
      extra = 1;
    } else if ((c & 0xF0U) == 0xE0U) {
      extra = 2;
    } else if ((c & 0xF8U) == 0xF0U && c <= 0xF4U) {
      extra = 3;
    } else {
      return false;
    }
    if (extra > 0 && i + extra >= s.size()) return false;  // sequence cut short
    for (std::size_t k = 1; k <= extra; ++k) {
      if ((static_cast<unsigned char>(s[i + k]) & 0xC0U) != 0x80U) return false;
    }
    i += extra + 1;
  }
  return true;
}

bool inside(std::span<const std::uint8_t> view, const Record& frame) {
  if (view.empty()) return true;
  const std::uint8_t* begin = frame.storage.data();
  const std::uint8_t* end = begin + frame.size;
  return view.data() >= begin && view.data() + view.size() <= end;
}

void check_views(const DecodedPdu& pdu, const Record& frame) {
  const rtu::PduHeader& h = rtu::pdu_header(pdu);
  if (!inside(h.data, frame)) fail("header data outside the frame", {});
  std::visit(
      [&frame](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, rtu::ReadRegistersResponse> ||
                      std::is_same_v<T, rtu::WriteMultipleRegistersRequest> ||
                      std::is_same_v<T, rtu::ReadWriteMultipleRequest> ||
                      std::is_same_v<T, rtu::FifoResponse>) {
          if (!inside(p.values.bytes(), frame)) fail("values outside the frame", {});
        } else if constexpr (std::is_same_v<T, rtu::ReadBitsResponse>) {
          if (!inside(p.bits.bytes(), frame)) fail("bits outside the frame", {});
        } else if constexpr (std::is_same_v<T, rtu::WriteMultipleCoilsRequest>) {
          if (!inside(p.coils.bytes(), frame)) fail("coils outside the frame", {});
        } else if constexpr (std::is_same_v<T, rtu::DeviceIdResponse>) {
          for (const auto& object : p.objects) {
            if (!inside(object.value, frame)) fail("object outside the frame", {});
          }
        } else if constexpr (std::is_same_v<T, rtu::FileRecordRequest> ||
                             std::is_same_v<T, rtu::ReadFileRecordResponse>) {
          for (const auto& record : p.records) {
            if (!inside(record.values.bytes(), frame)) fail("record outside the frame", {});
          }
        }
      },
      pdu);
}

void run(const Record& frame, Role role, const Record* request) {
  const DecodedPdu pdu = rtu::decode_pdu(frame, role);
  check_views(pdu, frame);
  const rtu::IssueSet issues = rtu::check_pdu(pdu);
  if (request != nullptr) (void)rtu::check_response_fits(*request, frame);

  fmt::memory_buffer json_text;
  rtu::JsonWriter json(json_text);
  json.begin_object();
  rtu::write_pdu_json(json, pdu);
  json.end_object();
  const std::string_view text(json_text.data(), json_text.size());
  if (!nlohmann::json::accept(text)) fail("invalid JSON", text);

  fmt::memory_buffer summary;
  rtu::append_pdu_summary(summary, pdu);
  const std::string_view line(summary.data(), summary.size());
  if (!valid_utf8(line)) fail("summary is not UTF-8", line);

  // Deterministic: a second decode gives the same JSON and issues.
  const DecodedPdu again = rtu::decode_pdu(frame, role);
  fmt::memory_buffer json_again;
  rtu::JsonWriter json2(json_again);
  json2.begin_object();
  rtu::write_pdu_json(json2, again);
  json2.end_object();
  if (std::string_view(json_again.data(), json_again.size()) != text)
    fail("not deterministic", text);
  if (rtu::check_pdu(again).bits() != issues.bits()) fail("issues not deterministic", text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::uint8_t> input(data, size);
  const unsigned mode = input[0] % 4U;
  std::span<const std::uint8_t> rest = input.subspan(1);
  if (mode == 3) {
    if (rest.empty()) return 0;
    const std::size_t request_size = std::min<std::size_t>(rest[0], rest.size() - 1);
    const Record request = make_record(rest.subspan(1, request_size));
    Record response = make_record(rest.subspan(1 + request_size));
    response.request = &request;
    const PoisonTail guard_request(request);
    const PoisonTail guard_response(response);
    run(request, Role::kRequest, nullptr);
    run(response, Role::kResponse, &request);
    return 0;
  }
  const Record frame = make_record(rest);
  const PoisonTail guard(frame);
  run(frame, mode == 0 ? Role::kRequest : mode == 1 ? Role::kResponse : Role::kUnknown, nullptr);
  return 0;
}
