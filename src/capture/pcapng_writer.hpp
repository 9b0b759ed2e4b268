#pragma once
// Incremental pcapng writer: one Section Header Block, any number of interfaces (each with
// its own link type and timestamp resolution), then Enhanced Packet Blocks as they come.
// Every block is built whole and handed to the ByteOutput in one write(), so a crash leaves
// a readable file up to the last flush(). Live capture calls flush() periodically.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "capture/byte_order.hpp"
#include "capture/byte_output.hpp"
#include "core/time.hpp"

namespace rtu {

struct PcapngInterface {
  std::uint16_t link_type = 0;
  std::string name;         // if_name, e.g. "/dev/ttyUSB0"; omitted when empty
  std::string description;  // if_description, e.g. "RS-485 9600 8E1"; omitted when empty
  // if_tsresol as decimal digits: 6 = µs, 9 = ns (0..9).
  std::uint8_t decimal_digits = 9;
  std::uint32_t snap_length = 0;  // 0 = no limit
};

// The optional parts of one packet.
struct PcapngPacketMeta {
  std::string_view comment;  // opt_comment; omitted when empty
  std::uint32_t flags = 0;   // epb_flags (pcap::kFlagsInbound / kFlagsOutbound ...); 0 = omitted
  // Length on the wire when larger than the bytes stored; 0 = same as the data.
  std::uint32_t original_length = 0;
};

class PcapngWriter {
 public:
  // Writes the Section Header Block at once; shb_userappl is "rtuscope <version>".
  explicit PcapngWriter(std::unique_ptr<ByteOutput> output, ByteOrder order = host_byte_order());
  PcapngWriter(const PcapngWriter&) = delete;
  PcapngWriter& operator=(const PcapngWriter&) = delete;
  ~PcapngWriter() = default;

  // Writes an Interface Description Block; returns its interface id (0, 1, ...).
  std::uint32_t add_interface(const PcapngInterface& interface);

  // Writes an Enhanced Packet Block. `t` is nanoseconds since 1970-01-01 UTC and is
  // truncated to the interface's resolution. Throws InputError for times before 1970
  // (pcapng cannot hold them) and std::out_of_range for an unknown interface.
  void write_packet(std::uint32_t interface_id, Nanos t, std::span<const std::uint8_t> data,
                    const PcapngPacketMeta& meta = {});

  void flush() { output_->flush(); }
  [[nodiscard]] ByteOutput& output() { return *output_; }
  [[nodiscard]] std::uint64_t packets_written() const { return packets_; }

 private:
  void begin_block(std::uint32_t type);
  void add_option(std::uint16_t code, std::span<const std::uint8_t> value);
  void add_option(std::uint16_t code, std::string_view text);
  void finish_block();

  std::unique_ptr<ByteOutput> output_;
  ByteOrder order_;
  std::vector<std::uint8_t> block_;  // reused for every block
  bool block_has_options_ = false;
  std::vector<std::uint8_t> interface_digits_;  // decimal digits per interface id
  std::uint64_t packets_ = 0;
};

// 10^digits for digits 0..9.
std::int64_t pow10_i64(unsigned digits);

}  // namespace rtu
