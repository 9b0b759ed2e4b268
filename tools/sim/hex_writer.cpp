#include "hex_writer.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "time_text.hpp"

namespace rtu::sim {

void write_hex_capture(std::ostream& out, const LineSettings& line, std::string_view command,
                       std::span<const WireByte> bytes, std::span<const OutputChunk> chunks) {
  fmt::memory_buffer buf;
  fmt::format_to(std::back_inserter(buf), "# baud={} parity={} stop={}\n", line.baud,
                 parity_letter(line.parity), line.stop_bits);
  fmt::format_to(std::back_inserter(buf), "# {}\n", command);
  for (const OutputChunk& c : chunks) {
    fmt::format_to(std::back_inserter(buf), "{}", seconds_text(c.t));
    for (std::size_t i = c.first; i < c.first + c.count; ++i) {
      fmt::format_to(std::back_inserter(buf), " {:02x}", bytes[i].value);
    }
    buf.push_back('\n');
    if (buf.size() > 1U << 16U) {
      out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
      buf.clear();
    }
  }
  out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

}  // namespace rtu::sim
