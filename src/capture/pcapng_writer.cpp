#include "capture/pcapng_writer.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "capture/field_cursor.hpp"
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
  const std::size_t comment_size = comment.empty() ? 0 : 4 + padded4(comment.size());
  const std::size_t flags_size = meta.flags != 0 ? 8 : 0;
  const std::size_t end_of_options = comment_size + flags_size > 0 ? 4 : 0;
  const std::size_t total =
      8 + 20 + padded4(data.size()) + comment_size + flags_size + end_of_options + 4;
  block_.resize(total);
  FieldCursor out(block_.data(), order_);
  out.put<std::uint32_t>(pcap::kBlockEnhancedPacket);
  out.put<std::uint32_t>(static_cast<std::uint32_t>(total));
  out.put<std::uint32_t>(interface_id);
  out.put<std::uint32_t>(static_cast<std::uint32_t>(ticks >> 32U));
  out.put<std::uint32_t>(static_cast<std::uint32_t>(ticks & 0xFFFFFFFFU));
  out.put<std::uint32_t>(captured);
  out.put<std::uint32_t>(meta.original_length > captured ? meta.original_length : captured);
  out.bytes(data, padded4(data.size()));
  if (comment_size != 0) {
    const std::span text(reinterpret_cast<const std::uint8_t*>(comment.data()), comment.size());
    out.tlv(pcap::kOptComment, static_cast<std::uint16_t>(comment.size()), text,
            padded4(comment.size()));
  }
  if (flags_size != 0) {
    out.put<std::uint16_t>(pcap::kEpbFlags);
    out.put<std::uint16_t>(4);
    out.put<std::uint32_t>(meta.flags);
  }
  if (end_of_options != 0) out.tlv(pcap::kOptEndOfOpt, 0, {}, 0);
  out.put<std::uint32_t>(static_cast<std::uint32_t>(total));
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
  const std::size_t at = block_.size();
  block_.resize(at + 4 + padded4(value.size()));
  FieldCursor(block_.data() + at, order_)
      .tlv(code, static_cast<std::uint16_t>(value.size()), value, padded4(value.size()));
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
