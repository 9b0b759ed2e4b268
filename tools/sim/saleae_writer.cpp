#include "saleae_writer.hpp"

#include <fmt/format.h>

#include "time_text.hpp"

namespace rtu::sim {

void write_saleae_table(std::ostream& out, std::span<const WireByte> bytes) {
  fmt::memory_buffer buf;
  fmt::format_to(std::back_inserter(buf), "name,type,start_time,duration,\"data\"\n");
  for (const WireByte& b : bytes) {
    fmt::format_to(std::back_inserter(buf), "\"Async Serial\",\"data\",{},{},0x{:02X}\n",
                   seconds_text(b.start), seconds_text(b.end - b.start), b.value);
    if (buf.size() > 1U << 16U) {
      out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
      buf.clear();
    }
  }
  out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

}  // namespace rtu::sim
