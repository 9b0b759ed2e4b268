#pragma once
// Constants of classic pcap and pcapng (pcap-savefile(5), draft-ietf-opsawg-pcapng) as far
// as rtuscope writes and reads them, and the two link types it uses.
#include <cstdint>

namespace rtu::pcap {

// Link types (tcpdump.org/linktypes.html).
inline constexpr std::uint16_t kLinkTypeRtacSerial = 250;  // raw serial chunks and line events
inline constexpr std::uint16_t kLinkTypeUpperPdu = 252;    // exported PDUs: one Modbus RTU ADU

// Classic pcap magic numbers, as integers in the writer's byte order.
inline constexpr std::uint32_t kMagicMicros = 0xA1B2C3D4;
inline constexpr std::uint32_t kMagicNanos = 0xA1B23C4D;
inline constexpr std::uint32_t kGlobalHeaderSize = 24;
inline constexpr std::uint32_t kRecordHeaderSize = 16;

// pcapng block types.
inline constexpr std::uint32_t kBlockSectionHeader = 0x0A0D0D0A;
inline constexpr std::uint32_t kBlockInterfaceDescription = 0x00000001;
inline constexpr std::uint32_t kBlockObsoletePacket = 0x00000002;
inline constexpr std::uint32_t kBlockSimplePacket = 0x00000003;
inline constexpr std::uint32_t kBlockEnhancedPacket = 0x00000006;
inline constexpr std::uint32_t kByteOrderMagic = 0x1A2B3C4D;

// Every block: type, total length, body, total length again.
inline constexpr std::uint32_t kBlockFramingSize = 12;
// Smallest legal total lengths (framing + fixed fields).
inline constexpr std::uint32_t kMinSectionHeaderSize = 28;
inline constexpr std::uint32_t kMinInterfaceDescriptionSize = 20;
inline constexpr std::uint32_t kMinEnhancedPacketSize = 32;
inline constexpr std::uint32_t kMinObsoletePacketSize = 32;

// Option codes.
inline constexpr std::uint16_t kOptEndOfOpt = 0;
inline constexpr std::uint16_t kOptComment = 1;
inline constexpr std::uint16_t kShbUserAppl = 4;
inline constexpr std::uint16_t kIfName = 2;
inline constexpr std::uint16_t kIfDescription = 3;
inline constexpr std::uint16_t kIfTsResol = 9;
inline constexpr std::uint16_t kIfTsOffset = 14;
inline constexpr std::uint16_t kEpbFlags = 2;

// epb_flags bits 0-1: direction of the packet.
inline constexpr std::uint32_t kFlagsInbound = 1;
inline constexpr std::uint32_t kFlagsOutbound = 2;
inline constexpr std::uint32_t kFlagsDirectionMask = 3;

// Anything larger than this in one record is damage, not data: serial records are tiny,
// and the bound keeps a corrupt length from allocating gigabytes.
inline constexpr std::uint32_t kMaxRecordSize = 16U * 1024U * 1024U;

}  // namespace rtu::pcap
