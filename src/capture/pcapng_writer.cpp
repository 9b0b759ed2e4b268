#include "capture/pcapng_writer.hpp"

#include <fmt/format.h>

#include <array>
#include <stdexcept>

#include "capture/pcap_format.hpp"
#include "core/input_error.hpp"

namespace rtu {

std::int64_t pow10_i64(unsigned digits) {
  std::int64_t p = 1;
  for (unsigned i = 0; i < digits; ++i) p *= 10;
  return p;
}

PcapngWriter::PcapngWriter(std::unique_ptr<ByteOutput> output, ByteOrder order)
    : output_(std::move(output)), order_(order) {
  block_.reserve(512);
  begin_block(pcap::kBlockSectionHeader);
  append<std::uint32_t>(block_, pcap::kByteOrderMagic, order_);
  append<std::uint16_t>(block_, 1, order_);                  // major
  append<std::uint16_t>(block_, 0, order_);                  // minor
  append<std::uint64_t>(block_, ~std::uint64_t{0}, order_);  // section length unknown
  add_option(pcap::kShbUserAppl, std::string_view("rtuscope " RTUSCOPE_VERSION));
  finish_block();
}

std::uint32_t PcapngWriter::add_interface(const PcapngInterface& interface) {
  if (interface.decimal_digits > 9) {
    throw std::invalid_argument("pcapng interface resolution must be 10^-0 .. 10^-9 s");
  }
  begin_block(pcap::kBlockInterfaceDescription);
  append<std::uint16_t>(block_, interface.link_type, order_);
  append<std::uint16_t>(block_, 0, order_);
  append<std::uint32_t>(block_, interface.snap_length, order_);
  if (!interface.name.empty()) add_option(pcap::kIfName, interface.name);
  if (!interface.description.empty()) add_option(pcap::kIfDescription, interface.description);
  const std::uint8_t resolution = interface.decimal_digits;
  add_option(pcap::kIfTsResol, std::span<const std::uint8_t>(&resolution, 1));
  finish_block();
  interface_digits_.push_back(interface.decimal_digits);
  return static_cast<std::uint32_t>(interface_digits_.size() - 1);
}

void PcapngWriter::write_packet(std::uint32_t interface_id, Nanos t,
                                std::span<const std::uint8_t> data, const PcapngPacketMeta& meta) {
  if (interface_id >= interface_digits_.size()) {
    throw std::out_of_range(fmt::format("pcapng: no interface {}", interface_id));
  }
  if (t < 0) {
    throw InputError(fmt::format("timestamp {:.9f} s is before 1970-01-01; pcapng cannot hold it",
                                 to_seconds(t)));
  }
  const auto ticks =
      static_cast<std::uint64_t>(t / pow10_i64(9U - interface_digits_[interface_id]));
  const auto captured = static_cast<std::uint32_t>(data.size());
  begin_block(pcap::kBlockEnhancedPacket);
  append<std::uint32_t>(block_, interface_id, order_);
  append<std::uint32_t>(block_, static_cast<std::uint32_t>(ticks >> 32U), order_);
  append<std::uint32_t>(block_, static_cast<std::uint32_t>(ticks & 0xFFFFFFFFU), order_);
  append<std::uint32_t>(block_, captured, order_);
  append<std::uint32_t>(block_, meta.original_length > captured ? meta.original_length : captured,
                        order_);
  block_.insert(block_.end(), data.begin(), data.end());
  while (block_.size() % 4 != 0) block_.push_back(0);
  if (!meta.comment.empty()) add_option(pcap::kOptComment, meta.comment);
  if (meta.flags != 0) {
    std::array<std::uint8_t, 4> flags{};
    put(flags.data(), meta.flags, order_);
    add_option(pcap::kEpbFlags, flags);
  }
  finish_block();
  ++packets_;
}

void PcapngWriter::begin_block(std::uint32_t type) {
  block_.clear();
  block_has_options_ = false;
  append<std::uint32_t>(block_, type, order_);
  append<std::uint32_t>(block_, 0, order_);  // total length, filled in by finish_block
}

void PcapngWriter::add_option(std::uint16_t code, std::span<const std::uint8_t> value) {
  if (value.size() > 0xFFFFU) throw std::length_error("pcapng option longer than 65535 bytes");
  append<std::uint16_t>(block_, code, order_);
  append<std::uint16_t>(block_, static_cast<std::uint16_t>(value.size()), order_);
  block_.insert(block_.end(), value.begin(), value.end());
  while (block_.size() % 4 != 0) block_.push_back(0);
  block_has_options_ = true;
}

void PcapngWriter::add_option(std::uint16_t code, std::string_view text) {
  if (text.size() > 0xFFFCU) text = text.substr(0, 0xFFFC);
  add_option(code, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

void PcapngWriter::finish_block() {
  if (block_has_options_) {
    append<std::uint16_t>(block_, pcap::kOptEndOfOpt, order_);
    append<std::uint16_t>(block_, 0, order_);
  }
  const auto total = static_cast<std::uint32_t>(block_.size() + 4);
  store<std::uint32_t>(block_, 4, total, order_);
  append<std::uint32_t>(block_, total, order_);
  output_->write(block_);
}

}  // namespace rtu
