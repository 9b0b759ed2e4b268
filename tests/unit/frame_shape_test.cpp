#include "framing/frame_shape.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace rtu {
namespace {

Shape req(std::vector<std::uint8_t> bytes) {
  return predict_shape(bytes, Role::kRequest);
}
Shape resp(std::vector<std::uint8_t> bytes) {
  return predict_shape(bytes, Role::kResponse);
}

TEST(FrameShape, EveryPublicFunctionHasARequestLength) {
  EXPECT_EQ(req({1, 0x01}), Shape::length(8));
  EXPECT_EQ(req({1, 0x02}), Shape::length(8));
  EXPECT_EQ(req({1, 0x03}), Shape::length(8));
  EXPECT_EQ(req({1, 0x04}), Shape::length(8));
  EXPECT_EQ(req({1, 0x05}), Shape::length(8));
  EXPECT_EQ(req({1, 0x06}), Shape::length(8));
  EXPECT_EQ(req({1, 0x07}), Shape::length(4));
  EXPECT_EQ(req({1, 0x08}), Shape::need(4));
  EXPECT_EQ(req({1, 0x08, 0x00, 0x0A}), Shape::length(8));
  EXPECT_EQ(req({1, 0x08, 0x00, 0x00}), Shape::unpredictable());
  EXPECT_EQ(req({1, 0x0B}), Shape::length(4));
  EXPECT_EQ(req({1, 0x0C}), Shape::length(4));
  EXPECT_EQ(req({1, 0x0F, 0, 0, 0, 10, 2}), Shape::length(11));
  EXPECT_EQ(req({1, 0x10, 0, 0, 0, 2}), Shape::need(7));
  EXPECT_EQ(req({1, 0x10, 0, 0, 0, 2, 4}), Shape::length(13));
  EXPECT_EQ(req({1, 0x11}), Shape::length(4));
  EXPECT_EQ(req({1, 0x14, 7}), Shape::length(12));
  EXPECT_EQ(req({1, 0x15, 9}), Shape::length(14));
  EXPECT_EQ(req({1, 0x16}), Shape::length(10));
  EXPECT_EQ(req({1, 0x17, 0, 0, 0, 1, 0, 0, 0, 1, 2}), Shape::length(15));
  EXPECT_EQ(req({1, 0x18}), Shape::length(6));
  EXPECT_EQ(req({1, 0x2B, 0x0E}), Shape::length(7));
  EXPECT_EQ(req({1, 0x2B, 0x0D}), Shape::unpredictable());
  EXPECT_EQ(req({1, 0x41}), Shape::unpredictable());
  EXPECT_EQ(req({1, 0x83}), Shape::impossible());
}

TEST(FrameShape, EveryPublicFunctionHasAResponseLength) {
  EXPECT_EQ(resp({1, 0x01, 1}), Shape::length(6));
  EXPECT_EQ(resp({1, 0x02, 3}), Shape::length(8));
  EXPECT_EQ(resp({1, 0x03, 6}), Shape::length(11));
  EXPECT_EQ(resp({1, 0x03, 3}), Shape::impossible()) << "register data is never odd";
  EXPECT_EQ(resp({1, 0x04, 2}), Shape::length(7));
  EXPECT_EQ(resp({1, 0x05}), Shape::length(8));
  EXPECT_EQ(resp({1, 0x06}), Shape::length(8));
  EXPECT_EQ(resp({1, 0x07}), Shape::length(5));
  EXPECT_EQ(resp({1, 0x0B}), Shape::length(8));
  EXPECT_EQ(resp({1, 0x0C, 8}), Shape::length(13));
  EXPECT_EQ(resp({1, 0x0F}), Shape::length(8));
  EXPECT_EQ(resp({1, 0x10}), Shape::length(8));
  EXPECT_EQ(resp({1, 0x11, 3}), Shape::length(8));
  EXPECT_EQ(resp({1, 0x14, 6}), Shape::length(11));
  EXPECT_EQ(resp({1, 0x15, 9}), Shape::length(14));
  EXPECT_EQ(resp({1, 0x16}), Shape::length(10));
  EXPECT_EQ(resp({1, 0x17, 4}), Shape::length(9));
  EXPECT_EQ(resp({1, 0x18, 0x00}), Shape::need(4));
  EXPECT_EQ(resp({1, 0x18, 0x00, 0x06}), Shape::length(12));
  EXPECT_EQ(resp({1, 0x83}), Shape::length(5));
  EXPECT_EQ(resp({0, 0x03, 2}), Shape::impossible()) << "broadcasts are never answered";
}

TEST(FrameShape, DeviceIdResponseWalksItsObjects) {
  std::vector<std::uint8_t> p = {1, 0x2B, 0x0E, 0x01, 0x01, 0x00, 0x00, 0x02};
  EXPECT_EQ(resp(p), Shape::need(10));
  p.insert(p.end(), {0x00, 0x03, 'A', 'B', 'C'});
  EXPECT_EQ(resp(p), Shape::need(15));
  p.insert(p.end(), {0x01, 0x01, 'x'});
  EXPECT_EQ(resp(p), Shape::length(18));
}

TEST(FrameShape, LengthsBeyondTheRtuMaximumAreImpossible) {
  EXPECT_EQ(resp({1, 0x18, 0x01, 0x00}), Shape::impossible());
}

}  // namespace
}  // namespace rtu
