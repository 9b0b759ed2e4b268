// append_pdu_summary(): one short line per PDU for the text output. Requests start with
// the function's short name, responses with "→". Addresses and register values are
// 0x%04X; long lists are cut after kMaxListed items with " …".
#include <iterator>

#include "core/function_codes.hpp"
#include "modbus/pdu.hpp"
#include "modbus/pdu_names.hpp"

namespace rtu {
namespace {

constexpr std::size_t kMaxListed = 8;       // words or bytes shown before " …"
constexpr std::size_t kMaxBitsListed = 32;  // coils shown before " …"
constexpr std::size_t kMaxTextListed = 32;  // characters of a device id value

using Out = fmt::memory_buffer;

template <typename... Args>
void put(Out& out, fmt::format_string<Args...> format, Args&&... args) {
  fmt::format_to(std::back_inserter(out), format, std::forward<Args>(args)...);
}

void put_words(Out& out, WordView words) {
  const std::size_t shown = words.size() < kMaxListed ? words.size() : kMaxListed;
  for (std::size_t i = 0; i < shown; ++i) put(out, " 0x{:04X}", words[i]);
  if (words.size() > shown) put(out, " …");
}

void put_bytes(Out& out, std::span<const std::uint8_t> bytes) {
  const std::size_t shown = bytes.size() < kMaxListed ? bytes.size() : kMaxListed;
  for (std::size_t i = 0; i < shown; ++i) put(out, " {:02X}", bytes[i]);
  if (bytes.size() > shown) put(out, " …");
}

// Coils as a 0/1 string, first coil first, grouped by 8.
void put_bits(Out& out, BitView bits) {
  if (bits.empty()) return;
  out.push_back(' ');
  const std::size_t shown = bits.size() < kMaxBitsListed ? bits.size() : kMaxBitsListed;
  for (std::size_t i = 0; i < shown; ++i) {
    if (i > 0 && i % 8 == 0) out.push_back(' ');
    out.push_back(bits[i] ? '1' : '0');
  }
  if (bits.size() > shown) put(out, " …");
}

void put_text(Out& out, std::span<const std::uint8_t> bytes) {
  out.push_back('"');
  const std::size_t shown = bytes.size() < kMaxTextListed ? bytes.size() : kMaxTextListed;
  for (std::size_t i = 0; i < shown; ++i) {
    const std::uint8_t b = bytes[i];
    out.push_back(b >= 0x20 && b < 0x7F ? static_cast<char>(b) : '.');
  }
  if (bytes.size() > shown) put(out, "…");
  out.push_back('"');
}

std::string_view name(const PduHeader& h) {
  return function_short_name(h.function);
}

std::string_view bits_noun(std::uint8_t function) {
  return function == fc::kReadDiscreteInputs ? "inputs" : "coils";
}

void summarize(Out& out, const RawPdu& p) {
  if (p.role == Role::kResponse) {
    put(out, "→ {}", name(p));
  } else {
    put(out, "{}", name(p));
  }
  if (!is_public_function(p.function & 0x7FU)) put(out, " 0x{:02X}", p.function);
  if (p.issues.has(IssueId::kTruncated)) put(out, " (truncated)");
  if (!p.data.empty()) {
    put(out, " {} bytes", p.data.size());
    put_bytes(out, p.data);
  }
}

void summarize(Out& out, const ExceptionResponse& p) {
  put(out, "exception {:02X} {}", p.code, exception_name(p.code));
}

void summarize(Out& out, const ReadRequest& p) {
  put(out, "{} 0x{:04X} ×{}", name(p), p.addr, p.qty);
}

void summarize(Out& out, const ReadBitsResponse& p) {
  put(out, "→ {} {}", p.bits.size(), bits_noun(p.function));
  put_bits(out, p.bits);
}

void summarize(Out& out, const ReadRegistersResponse& p) {
  put(out, "→ {} regs", p.values.size());
  put_words(out, p.values);
}

void summarize(Out& out, const WriteSingle& p) {
  const bool response = p.role == Role::kResponse;
  if (p.function == fc::kWriteSingleCoil) {
    put(out, "{} 0x{:04X} = ", response ? "→ coil" : "write coil", p.addr);
    if (const auto on = p.coil()) {
      put(out, "{}", *on ? "ON" : "OFF");
    } else {
      put(out, "0x{:04X} (invalid)", p.value);
    }
    return;
  }
  put(out, "{} 0x{:04X} = 0x{:04X}", response ? "→ register" : "write register", p.addr, p.value);
}

void summarize(Out& out, const WriteMultipleCoilsRequest& p) {
  put(out, "{} 0x{:04X} ×{} =", name(p), p.addr, p.qty);
  put_bits(out, p.coils);
}

void summarize(Out& out, const WriteMultipleRegistersRequest& p) {
  put(out, "{} 0x{:04X} ×{} =", name(p), p.addr, p.qty);
  put_words(out, p.values);
}

void summarize(Out& out, const WriteMultipleResponse& p) {
  put(out, "→ wrote {} 0x{:04X} ×{}", p.function == fc::kWriteMultipleCoils ? "coils" : "registers",
      p.addr, p.qty);
}

void summarize(Out& out, const NoDataRequest& p) {
  put(out, "{}", name(p));
}

void summarize(Out& out, const ExceptionStatusResponse& p) {
  put(out, "→ status 0x{:02X}", p.status);
}

void summarize(Out& out, const DiagnosticsPdu& p) {
  put(out, "{} {:02X} {}", p.role == Role::kResponse ? "→" : "diagnostics", p.sub_function,
      diagnostics_sub_function_name(p.sub_function));
  put_bytes(out, p.payload);
}

void summarize(Out& out, const CommEventCounterResponse& p) {
  put(out, "→ status 0x{:04X} events {}", p.status, p.event_count);
}

void summarize(Out& out, const CommEventLogResponse& p) {
  put(out, "→ status 0x{:04X} events {} messages {} log", p.status, p.event_count, p.message_count);
  put_bytes(out, p.events);
}

void summarize(Out& out, const ServerIdResponse& p) {
  put(out, "→ {} bytes", p.payload.size());
  put_bytes(out, p.payload);
}

void summarize(Out& out, const FileRecordRequest& p) {
  if (p.role == Role::kResponse) {
    put(out, "→ wrote");
  } else {
    put(out, "{}", name(p));
  }
  std::size_t n = 0;
  for (const FileSubRecord& r : p.records) {
    if (n == kMaxListed) {
      put(out, " …");
      break;
    }
    put(out, "{} #{} rec {} ×{}", n == 0 ? "" : ",", r.file, r.record, r.record_length);
    ++n;
  }
}

void summarize(Out& out, const ReadFileRecordResponse& p) {
  put(out, "→ {} records", p.records.count());
  std::size_t n = 0;
  for (const FileSubRecord& r : p.records) {
    if (n == kMaxListed) {
      put(out, " …");
      break;
    }
    put(out, "{} {} regs", n == 0 ? ":" : ",", r.values.size());
    ++n;
  }
}

void summarize(Out& out, const MaskWrite& p) {
  put(out, "{} 0x{:04X} and 0x{:04X} or 0x{:04X}",
      p.role == Role::kResponse ? "→ mask" : "mask write", p.addr, p.and_mask, p.or_mask);
}

void summarize(Out& out, const ReadWriteMultipleRequest& p) {
  put(out, "read 0x{:04X} ×{} write 0x{:04X} ×{} =", p.read_addr, p.read_qty, p.write_addr,
      p.write_qty);
  put_words(out, p.values);
}

void summarize(Out& out, const FifoRequest& p) {
  put(out, "{} 0x{:04X}", name(p), p.addr);
}

void summarize(Out& out, const FifoResponse& p) {
  put(out, "→ {} values", p.fifo_count);
  put_words(out, p.values);
}

void summarize(Out& out, const DeviceIdRequest& p) {
  const std::string_view code = read_device_id_code_name(p.read_device_id_code);
  put(out, "read device id {} from 0x{:02X}", code.empty() ? "?" : code, p.object_id);
}

void summarize(Out& out, const DeviceIdResponse& p) {
  put(out, "→ conformity 0x{:02X}", p.conformity);
  if (p.more_follows != 0) put(out, " more from 0x{:02X}", p.next_object_id);
  std::size_t n = 0;
  for (const DeviceIdObject& o : p.objects) {
    if (n == kMaxListed) {
      put(out, " …");
      break;
    }
    const std::string_view object = device_id_object_name(o.id);
    if (object.empty()) {
      put(out, "{}0x{:02X}=", n == 0 ? " " : ", ", o.id);
    } else {
      put(out, "{}{}=", n == 0 ? " " : ", ", object);
    }
    put_text(out, o.value);
    ++n;
  }
}

void summarize(Out& out, const MeiPdu& p) {
  put(out, "{}mei 0x{:02X}", p.role == Role::kResponse ? "→ " : "", p.mei);
  if (!p.payload.empty()) {
    put(out, " {} bytes", p.payload.size());
    put_bytes(out, p.payload);
  }
}

}  // namespace

void append_pdu_summary(fmt::memory_buffer& out, const DecodedPdu& pdu) {
  std::visit([&out](const auto& p) { summarize(out, p); }, pdu);
}

}  // namespace rtu
