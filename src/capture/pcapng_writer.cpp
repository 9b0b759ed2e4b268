#include "capture/pcapng_writer.hpp"

#include <fmt/format.h>

#include <cstring>
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
  // A comment is cut where add_option(code, text) cuts one: at most 0xFFFC bytes.
  const std::string_view comment = meta.comment.substr(0, 0xFFFC);
  // Every frame of an export and every read of a recording comes here: the block is sized
  // once and written in place, the same bytes begin_block/add_option/finish_block give.
  const auto padded = [](std::size_t n) { return (n + 3U) & ~std::size_t{3}; };
  const std::size_t comment_size = comment.empty() ? 0 : 4 + padded(comment.size());
  const std::size_t flags_size = meta.flags != 0 ? 8 : 0;
  const std::size_t end_of_options = comment_size + flags_size > 0 ? 4 : 0;
  const std::size_t total =
      8 + 20 + padded(data.size()) + comment_size + flags_size + end_of_options + 4;
  block_.resize(total);
  std::uint8_t* p = block_.data();
  put<std::uint32_t>(p, pcap::kBlockEnhancedPacket, order_);
  put<std::uint32_t>(p + 4, static_cast<std::uint32_t>(total), order_);
  put<std::uint32_t>(p + 8, interface_id, order_);
  put<std::uint32_t>(p + 12, static_cast<std::uint32_t>(ticks >> 32U), order_);
  put<std::uint32_t>(p + 16, static_cast<std::uint32_t>(ticks & 0xFFFFFFFFU), order_);
  put<std::uint32_t>(p + 20, captured, order_);
  put<std::uint32_t>(p + 24, meta.original_length > captured ? meta.original_length : captured,
                     order_);
  p += 28;
  const auto copy_padded = [&](std::span<const std::uint8_t> bytes) {
    if (!bytes.empty()) std::memcpy(p, bytes.data(), bytes.size());
    std::memset(p + bytes.size(), 0, padded(bytes.size()) - bytes.size());
    p += padded(bytes.size());
  };
  copy_padded(data);
  if (comment_size != 0) {
    put<std::uint16_t>(p, pcap::kOptComment, order_);
    put<std::uint16_t>(p + 2, static_cast<std::uint16_t>(comment.size()), order_);
    p += 4;
    copy_padded(std::span(reinterpret_cast<const std::uint8_t*>(comment.data()), comment.size()));
  }
  if (flags_size != 0) {
    put<std::uint16_t>(p, pcap::kEpbFlags, order_);
    put<std::uint16_t>(p + 2, 4, order_);
    put<std::uint32_t>(p + 4, meta.flags, order_);
    p += 8;
  }
  if (end_of_options != 0) {
    put<std::uint16_t>(p, pcap::kOptEndOfOpt, order_);
    put<std::uint16_t>(p + 2, 0, order_);
    p += 4;
  }
  put<std::uint32_t>(p, static_cast<std::uint32_t>(total), order_);
  output_->write(block_);
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
