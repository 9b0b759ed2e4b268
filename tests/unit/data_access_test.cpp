// data_access() for every data function, from real frames with their CRC: ranges, values,
// byte counts that do not fit, truncated frames, exceptions, FC05's invalid values, FC23.
// Most frames are the examples of MODBUS Application Protocol V1.1b3 §6 (slave 0x11).
#include "modbus/data_access.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "pdu_test_support.hpp"

namespace rtu {
namespace {

using test::frame_with_crc;

using test::bits;
using test::words;

// True when `view` lies inside the record's bytes (the access copies nothing).
bool inside(std::span<const std::uint8_t> view, const Record& r) {
  const auto all = r.bytes();
  return !view.empty() && view.data() >= all.data() &&
         view.data() + view.size() <= all.data() + all.size();
}

TEST(DataAccess, TablesOfFunctions) {
  EXPECT_EQ(data_table_of(1), DataTable::kCoils);
  EXPECT_EQ(data_table_of(5), DataTable::kCoils);
  EXPECT_EQ(data_table_of(15), DataTable::kCoils);
  EXPECT_EQ(data_table_of(2), DataTable::kDiscreteInputs);
  for (const int f : {3, 6, 16, 22, 23}) {
    EXPECT_EQ(data_table_of(static_cast<std::uint8_t>(f)), DataTable::kHoldingRegisters) << f;
  }
  EXPECT_EQ(data_table_of(4), DataTable::kInputRegisters);
  for (const int f : {0, 7, 8, 11, 17, 20, 21, 24, 43, 0x83, 0x90}) {
    EXPECT_FALSE(data_table_of(static_cast<std::uint8_t>(f)).has_value()) << f;
  }
  EXPECT_EQ(data_table_name(DataTable::kCoils), "coil");
  EXPECT_EQ(data_table_name(DataTable::kDiscreteInputs), "discrete");
  EXPECT_EQ(data_table_name(DataTable::kHoldingRegisters), "holding");
  EXPECT_EQ(data_table_name(DataTable::kInputRegisters), "input");
  EXPECT_TRUE(is_bit_table(DataTable::kCoils));
  EXPECT_TRUE(is_bit_table(DataTable::kDiscreteInputs));
  EXPECT_FALSE(is_bit_table(DataTable::kHoldingRegisters));
  EXPECT_FALSE(is_bit_table(DataTable::kInputRegisters));
}

TEST(DataAccess, ReadCoilsTakesBitsFromResponseClippedToQuantity) {
  const Record req = frame_with_crc("11 01 00 13 00 13");
  const Record rsp = frame_with_crc("11 01 03 CD 6B 05");
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 1);
  const DataBlock& b = a.blocks[0];
  EXPECT_EQ(b.table, DataTable::kCoils);
  EXPECT_EQ(b.addr, 0x13);
  EXPECT_EQ(b.qty, 19);
  EXPECT_FALSE(b.write);
  EXPECT_TRUE(b.has_values);
  EXPECT_TRUE(b.count_fits);
  // CD 6B 05, LSB first; 19 of the 24 bits.
  EXPECT_EQ(bits(b.bits),
            (std::vector<int>{1, 0, 1, 1, 0, 0, 1, 1, 1, 1, 0, 1, 0, 1, 1, 0, 1, 0, 1}));
  EXPECT_TRUE(b.words.empty());
  EXPECT_TRUE(inside(b.bits.bytes(), rsp));
  EXPECT_TRUE(a.issues.empty());
  EXPECT_EQ(a.read(), &a.blocks[0]);
  EXPECT_EQ(a.write(), nullptr);
}

TEST(DataAccess, ReadWithoutResponseHasRangeButNoValues) {
  const Record req = frame_with_crc("11 01 00 13 00 13");
  const DataAccess a = data_access(req, nullptr);
  ASSERT_EQ(a.count, 1);
  EXPECT_EQ(a.blocks[0].addr, 0x13);
  EXPECT_EQ(a.blocks[0].qty, 19);
  EXPECT_FALSE(a.blocks[0].has_values);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_TRUE(a.blocks[0].bits.empty());
}

TEST(DataAccess, ReadDiscreteInputs) {
  const Record req = frame_with_crc("11 02 00 C4 00 16");
  const Record rsp = frame_with_crc("11 02 03 AC DB 35");
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 1);
  const DataBlock& b = a.blocks[0];
  EXPECT_EQ(b.table, DataTable::kDiscreteInputs);
  EXPECT_EQ(b.addr, 0xC4);
  EXPECT_EQ(b.qty, 22);
  EXPECT_TRUE(b.count_fits);
  ASSERT_EQ(b.bits.size(), 22U);
  EXPECT_FALSE(b.bits[0]);  // AC = 1010 1100
  EXPECT_TRUE(b.bits[2]);
  EXPECT_TRUE(b.bits[21]);  // 35 = 0011 0101: bit 5
}

TEST(DataAccess, ReadHoldingRegisters) {
  const Record req = frame_with_crc("11 03 00 6B 00 03");
  const Record rsp = frame_with_crc("11 03 06 02 2B 00 00 00 64");
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 1);
  const DataBlock& b = a.blocks[0];
  EXPECT_EQ(b.table, DataTable::kHoldingRegisters);
  EXPECT_EQ(b.addr, 0x6B);
  EXPECT_EQ(b.qty, 3);
  EXPECT_FALSE(b.write);
  EXPECT_TRUE(b.has_values);
  EXPECT_TRUE(b.count_fits);
  EXPECT_EQ(words(b.words), (std::vector<unsigned>{0x022B, 0x0000, 0x0064}));
  EXPECT_TRUE(b.bits.empty());
  EXPECT_TRUE(inside(b.words.bytes(), rsp));
}

TEST(DataAccess, ReadInputRegisters) {
  const Record req = frame_with_crc("11 04 00 08 00 01");
  const Record rsp = frame_with_crc("11 04 02 00 0A");
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 1);
  EXPECT_EQ(a.blocks[0].table, DataTable::kInputRegisters);
  EXPECT_EQ(a.blocks[0].addr, 8);
  EXPECT_TRUE(a.blocks[0].count_fits);
  EXPECT_EQ(words(a.blocks[0].words), (std::vector<unsigned>{0x000A}));
}

TEST(DataAccess, WriteSingleCoilOnAndOff) {
  const Record on = frame_with_crc("11 05 00 AC FF 00");
  const DataAccess a = data_access(on, &on);  // the response is an echo
  ASSERT_EQ(a.count, 1);
  const DataBlock& b = a.blocks[0];
  EXPECT_EQ(b.table, DataTable::kCoils);
  EXPECT_EQ(b.addr, 0xAC);
  EXPECT_EQ(b.qty, 1);
  EXPECT_TRUE(b.write);
  EXPECT_TRUE(b.has_values);
  EXPECT_TRUE(b.count_fits);
  EXPECT_FALSE(b.invalid_value);
  EXPECT_EQ(bits(b.bits), (std::vector<int>{1}));
  EXPECT_EQ(a.write(), &a.blocks[0]);
  EXPECT_EQ(a.read(), nullptr);

  const Record off = frame_with_crc("11 05 00 AC 00 00");
  EXPECT_EQ(bits(data_access(off, nullptr).blocks[0].bits), (std::vector<int>{0}));
}

TEST(DataAccess, WriteSingleCoilInvalidValueHasNoValue) {
  for (const char* hex : {"11 05 00 AC 12 34", "11 05 00 AC 00 FF", "11 05 00 AC FF 01"}) {
    const Record req = frame_with_crc(hex);
    const DataAccess a = data_access(req, nullptr);
    ASSERT_EQ(a.count, 1) << hex;
    EXPECT_TRUE(a.blocks[0].invalid_value) << hex;
    EXPECT_FALSE(a.blocks[0].has_values) << hex;
    EXPECT_TRUE(a.blocks[0].bits.empty()) << hex;
    EXPECT_EQ(a.blocks[0].addr, 0xAC) << hex;
  }
}

TEST(DataAccess, WriteSingleRegisterTakesValueFromRequest) {
  const Record req = frame_with_crc("11 06 00 01 00 03");
  const DataAccess a = data_access(req, nullptr);
  ASSERT_EQ(a.count, 1);
  const DataBlock& b = a.blocks[0];
  EXPECT_EQ(b.table, DataTable::kHoldingRegisters);
  EXPECT_EQ(b.addr, 1);
  EXPECT_EQ(b.qty, 1);
  EXPECT_TRUE(b.write);
  EXPECT_TRUE(b.has_values);
  EXPECT_TRUE(b.count_fits);
  EXPECT_EQ(words(b.words), (std::vector<unsigned>{3}));
  EXPECT_TRUE(inside(b.words.bytes(), req));
}

TEST(DataAccess, WriteMultipleCoils) {
  const Record req = frame_with_crc("11 0F 00 13 00 0A 02 CD 01");
  const Record rsp = frame_with_crc("11 0F 00 13 00 0A");
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 1);
  const DataBlock& b = a.blocks[0];
  EXPECT_EQ(b.table, DataTable::kCoils);
  EXPECT_EQ(b.addr, 0x13);
  EXPECT_EQ(b.qty, 10);
  EXPECT_TRUE(b.write);
  EXPECT_TRUE(b.has_values);
  EXPECT_TRUE(b.count_fits);
  EXPECT_EQ(bits(b.bits), (std::vector<int>{1, 0, 1, 1, 0, 0, 1, 1, 1, 0}));
  EXPECT_TRUE(inside(b.bits.bytes(), req));
  EXPECT_TRUE(a.issues.empty());
}

TEST(DataAccess, WriteMultipleRegisters) {
  const Record req = frame_with_crc("11 10 00 01 00 02 04 00 0A 01 02");
  const DataAccess a = data_access(req, nullptr);
  ASSERT_EQ(a.count, 1);
  const DataBlock& b = a.blocks[0];
  EXPECT_EQ(b.table, DataTable::kHoldingRegisters);
  EXPECT_EQ(b.addr, 1);
  EXPECT_EQ(b.qty, 2);
  EXPECT_TRUE(b.write);
  EXPECT_TRUE(b.has_values);
  EXPECT_TRUE(b.count_fits);
  EXPECT_EQ(words(b.words), (std::vector<unsigned>{0x000A, 0x0102}));
}

TEST(DataAccess, MaskWriteHasAddressButNoValue) {
  const Record req = frame_with_crc("11 16 00 04 00 F2 00 25");
  const DataAccess a = data_access(req, &req);
  ASSERT_EQ(a.count, 1);
  const DataBlock& b = a.blocks[0];
  EXPECT_EQ(b.table, DataTable::kHoldingRegisters);
  EXPECT_EQ(b.addr, 4);
  EXPECT_EQ(b.qty, 1);
  EXPECT_TRUE(b.write);
  EXPECT_FALSE(b.has_values);
  EXPECT_TRUE(b.count_fits);
  EXPECT_TRUE(b.words.empty());
}

TEST(DataAccess, ReadWriteMultipleWritesThenReads) {
  const Record req = frame_with_crc("11 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF");
  const Record rsp = frame_with_crc("11 17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF");
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 2);
  const DataBlock& w = a.blocks[0];
  EXPECT_TRUE(w.write);
  EXPECT_EQ(w.table, DataTable::kHoldingRegisters);
  EXPECT_EQ(w.addr, 0x0E);
  EXPECT_EQ(w.qty, 3);
  EXPECT_TRUE(w.has_values);
  EXPECT_TRUE(w.count_fits);
  EXPECT_EQ(words(w.words), (std::vector<unsigned>{0x00FF, 0x00FF, 0x00FF}));
  EXPECT_TRUE(inside(w.words.bytes(), req));
  const DataBlock& r = a.blocks[1];
  EXPECT_FALSE(r.write);
  EXPECT_EQ(r.table, DataTable::kHoldingRegisters);
  EXPECT_EQ(r.addr, 3);
  EXPECT_EQ(r.qty, 6);
  EXPECT_TRUE(r.has_values);
  EXPECT_TRUE(r.count_fits);
  EXPECT_EQ(words(r.words),
            (std::vector<unsigned>{0x00FE, 0x0ACD, 0x0001, 0x0003, 0x000D, 0x00FF}));
  EXPECT_TRUE(inside(r.words.bytes(), rsp));
  EXPECT_EQ(a.write(), &w);
  EXPECT_EQ(a.read(), &r);
  EXPECT_TRUE(a.issues.empty());
}

TEST(DataAccess, ReadWriteMultipleWithoutResponseStillWrites) {
  const Record req = frame_with_crc("11 17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF");
  const Record exception = frame_with_crc("11 97 02");
  for (const Record* rsp : {static_cast<const Record*>(nullptr), &exception}) {
    const DataAccess a = data_access(req, rsp);
    ASSERT_EQ(a.count, 2);
    EXPECT_TRUE(a.blocks[0].has_values);
    EXPECT_FALSE(a.blocks[1].has_values);
    EXPECT_TRUE(a.blocks[1].words.empty());
  }
}

TEST(DataAccess, ReadWriteMultipleWriteByteCountWrong) {
  // Three registers to write, but the byte count says 4 (and 4 bytes follow).
  const Record req = frame_with_crc("11 17 00 03 00 01 00 0E 00 03 04 00 01 00 02");
  const DataAccess a = data_access(req, nullptr);
  ASSERT_EQ(a.count, 2);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_EQ(words(a.blocks[0].words), (std::vector<unsigned>{1, 2}));
  EXPECT_EQ(a.blocks[1].addr, 3);
  EXPECT_EQ(a.blocks[1].qty, 1);
}

TEST(DataAccess, ResponseByteCountShortOfQuantity) {
  // Three registers asked, the byte count announces two and two follow.
  const Record req = frame_with_crc("11 03 00 6B 00 03");
  const Record rsp = frame_with_crc("11 03 04 02 2B 00 00");
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 1);
  EXPECT_TRUE(a.blocks[0].has_values);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_EQ(words(a.blocks[0].words), (std::vector<unsigned>{0x022B, 0}));
  EXPECT_TRUE(a.issues.empty());  // the response itself is consistent
}

TEST(DataAccess, ResponseLongerThanQuantityIsClipped) {
  const Record req = frame_with_crc("11 03 00 6B 00 01");
  const Record rsp = frame_with_crc("11 03 04 02 2B 00 07");
  const DataAccess a = data_access(req, &rsp);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_EQ(words(a.blocks[0].words), (std::vector<unsigned>{0x022B}));
}

TEST(DataAccess, ResponseByteCountBeyondFrame) {
  // Byte count 6, but only three bytes follow: one whole register.
  const Record req = frame_with_crc("11 03 00 6B 00 03");
  const Record rsp = frame_with_crc("11 03 06 02 2B 00");
  const DataAccess a = data_access(req, &rsp);
  EXPECT_TRUE(a.blocks[0].has_values);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_EQ(words(a.blocks[0].words), (std::vector<unsigned>{0x022B}));
  EXPECT_TRUE(a.issues.has(IssueId::kByteCount));
}

TEST(DataAccess, BitResponseByteCountWrong) {
  // 19 coils need 3 bytes; the count says 2 and 2 follow: 16 bits.
  const Record req = frame_with_crc("11 01 00 13 00 13");
  const Record rsp = frame_with_crc("11 01 02 CD 6B");
  const DataAccess a = data_access(req, &rsp);
  EXPECT_TRUE(a.blocks[0].has_values);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_EQ(a.blocks[0].bits.size(), 16U);
}

TEST(DataAccess, WriteMultipleRegistersByteCountWrong) {
  // Two registers, byte count 6 with 6 bytes: the third word is not part of the write.
  const Record req = frame_with_crc("11 10 00 01 00 02 06 00 0A 01 02 03 04");
  const DataAccess a = data_access(req, nullptr);
  EXPECT_TRUE(a.blocks[0].has_values);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_EQ(words(a.blocks[0].words), (std::vector<unsigned>{0x000A, 0x0102}));
}

TEST(DataAccess, WriteMultipleCoilsByteCountShort) {
  // Ten coils need 2 bytes; the count says 1 and 1 follows: 8 coils known.
  const Record req = frame_with_crc("11 0F 00 13 00 0A 01 CD");
  const DataAccess a = data_access(req, nullptr);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_EQ(bits(a.blocks[0].bits), (std::vector<int>{1, 0, 1, 1, 0, 0, 1, 1}));
}

TEST(DataAccess, WriteMultipleRegistersDataCutShort) {
  // Byte count 4, two bytes present: one register, and the decode notes the byte count.
  const Record req = frame_with_crc("11 10 00 01 00 02 04 00 0A");
  const DataAccess a = data_access(req, nullptr);
  ASSERT_EQ(a.count, 1);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_EQ(words(a.blocks[0].words), (std::vector<unsigned>{0x000A}));
  EXPECT_TRUE(a.issues.has(IssueId::kByteCount));
}

TEST(DataAccess, TruncatedRequestsAccessNothing) {
  for (const char* hex : {"11 03 00 6B", "11 05 00 AC FF", "11 10 00 01 00 02", "11 16 00 04 00",
                          "11 17 00 03 00 06 00 0E 00 03", "11"}) {
    const Record req = frame_with_crc(hex);
    const DataAccess a = data_access(req, nullptr);
    EXPECT_TRUE(a.empty()) << hex;
    EXPECT_EQ(a.read(), nullptr) << hex;
    EXPECT_TRUE(a.issues.has(IssueId::kTruncated)) << hex;
  }
}

TEST(DataAccess, TruncatedResponseGivesNoValues) {
  const Record req = frame_with_crc("11 03 00 6B 00 03");
  const Record rsp = frame_with_crc("11 03");  // no byte count
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 1);
  EXPECT_FALSE(a.blocks[0].has_values);
  EXPECT_FALSE(a.blocks[0].count_fits);
  EXPECT_TRUE(a.issues.has(IssueId::kTruncated));
}

TEST(DataAccess, ExceptionResponseGivesNoValues) {
  const Record req = frame_with_crc("11 01 00 13 00 13");
  const Record rsp = frame_with_crc("11 81 02");
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 1);
  EXPECT_EQ(a.blocks[0].qty, 19);
  EXPECT_FALSE(a.blocks[0].has_values);
  EXPECT_TRUE(a.blocks[0].bits.empty());
  EXPECT_TRUE(a.issues.empty());
}

TEST(DataAccess, ResponseOfAnotherFunctionIsIgnored) {
  const Record req = frame_with_crc("11 03 00 6B 00 01");
  const Record rsp = frame_with_crc("11 04 02 00 0A");
  const DataAccess a = data_access(req, &rsp);
  ASSERT_EQ(a.count, 1);
  EXPECT_FALSE(a.blocks[0].has_values);
}

TEST(DataAccess, OtherFunctionsAccessNoTable) {
  for (const char* hex :
       {"11 07", "11 08 00 00 A5 37", "11 11", "11 18 04 DE", "11 2B 0E 01 00", "11 83 02"}) {
    const Record req = frame_with_crc(hex);
    EXPECT_TRUE(data_access(req, nullptr).empty()) << hex;
  }
}

}  // namespace
}  // namespace rtu
