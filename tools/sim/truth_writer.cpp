#include "truth_writer.hpp"

#include <fmt/format.h>

#include "time_text.hpp"

namespace rtu::sim {
namespace {

void put_string(fmt::memory_buffer& buf, std::string_view s) {
  buf.push_back('"');
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      buf.push_back('\\');
      buf.push_back(c);
    } else if (static_cast<unsigned char>(c) < 0x20) {
      fmt::format_to(std::back_inserter(buf), "\\u{:04x}", static_cast<unsigned>(c));
    } else {
      buf.push_back(c);
    }
  }
  buf.push_back('"');
}

class Out {
 public:
  explicit Out(fmt::memory_buffer& buf) : buf_(buf) {}
  template <typename... Args>
  void operator()(fmt::format_string<Args...> f, Args&&... args) {
    fmt::format_to(std::back_inserter(buf_), f, std::forward<Args>(args)...);
  }

 private:
  fmt::memory_buffer& buf_;
};

}  // namespace

void write_truth(std::ostream& out, const LineSettings& line, std::string_view command,
                 const Timeline& timeline) {
  fmt::memory_buffer buf;
  Out put(buf);
  put("{{\"kind\":\"capture\",\"generator\":");
  put_string(buf, command);
  put(",\"baud\":{},\"parity\":\"{}\",\"stop\":{},\"bits_per_char\":{},\"records\":{},"
      "\"bytes\":{}}}\n",
      line.baud, parity_letter(line.parity), line.stop_bits, line.bits_per_char(),
      timeline.records().size(), timeline.bytes().size());
  for (const TruthRecord& r : timeline.records()) {
    const bool frame = r.kind == TruthKind::kFrame;
    put("{{\"kind\":\"{}\",\"t\":{},\"t_end\":{},\"hex\":\"", frame ? "frame" : "noise",
        seconds_text(r.t_start), seconds_text(r.t_end));
    for (const std::uint8_t b : r.bytes) put("{:02x}", b);
    buf.push_back('"');
    if (frame) {
      put(",\"slave\":{}", r.bytes.empty() ? 0 : r.bytes[0]);
      if (r.bytes.size() >= 2) {
        put(",\"fc\":{}", r.bytes[1]);
      } else {
        put(",\"fc\":null");
      }
      put(",\"role\":\"{}\"", r.role == TruthRole::kRequest ? "request" : "response");
      if (r.txn) {
        put(",\"txn\":{}", *r.txn);
      } else {
        put(",\"txn\":null");
      }
      put(",\"device\":\"{}\",\"faults\":[", r.device);
      for (std::size_t i = 0; i < r.faults.size(); ++i) {
        if (i > 0) buf.push_back(',');
        put("\"{}\"", r.faults[i]);
      }
      buf.push_back(']');
      if (!r.flipped.empty()) {
        put(",\"flipped\":[");
        for (std::size_t i = 0; i < r.flipped.size(); ++i) {
          if (i > 0) buf.push_back(',');
          put("{}", r.flipped[i]);
        }
        buf.push_back(']');
      }
      if (r.intended_size > 0) put(",\"intended_size\":{}", r.intended_size);
    } else {
      put(",\"cause\":\"{}\"", r.cause);
    }
    put("}}\n");
    if (buf.size() > 1U << 16U) {
      out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
      buf.clear();
    }
  }
  out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

}  // namespace rtu::sim
