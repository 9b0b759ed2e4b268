#include "core/function_codes.hpp"

#include <gtest/gtest.h>

#include <set>

namespace rtu {
namespace {

// The public codes of MODBUS Application Protocol V1.1b3 §6, written out here apart from the
// table the product reads.
const std::set<int> kSpecCodes = {1,  2,  3,  4,  5,  6,  7,  8,  11, 12,
                                  15, 16, 17, 20, 21, 22, 23, 24, 43};

TEST(FunctionCodes, EveryCodeIsPublicExactlyWhereTheSpecificationDefinesIt) {
  for (int code = 0; code < 256; ++code) {
    const auto function = static_cast<std::uint8_t>(code);
    EXPECT_EQ(is_public_function(function), kSpecCodes.count(code) == 1) << "code " << code;
  }
}

TEST(FunctionCodes, APublicCodeHasAName) {
  for (int code = 0; code < 128; ++code) {
    const auto function = static_cast<std::uint8_t>(code);
    const bool named = function_name(function) != "Unknown function" &&
                       function_name(function) != "User-defined function";
    EXPECT_EQ(named, is_public_function(function)) << "code " << code;
  }
}

}  // namespace
}  // namespace rtu
