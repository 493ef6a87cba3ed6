// core/color's 8-bit sRGB decode table, shared by baking, the material model and the preview.
#include <gtest/gtest.h>

#include "core/color.hpp"

namespace gltf_pbr {
namespace {

TEST(Srgb8Table, EqualsTheTransferFunctionAtEveryCodeAndIncreases) {
  for (int code = 0; code < 256; ++code) {
    const auto byte = static_cast<std::uint8_t>(code);
    EXPECT_EQ(srgb8_to_linear(byte), srgb_to_linear(static_cast<float>(code) / 255.0f)) << code;
    EXPECT_EQ(srgb8_to_linear_table()[byte], srgb8_to_linear(byte));
    if (code > 0) {
      EXPECT_LT(srgb8_to_linear(static_cast<std::uint8_t>(code - 1)), srgb8_to_linear(byte)) << code;
    }
  }
  EXPECT_EQ(srgb8_to_linear(0), 0.0f);
  EXPECT_FLOAT_EQ(srgb8_to_linear(255), 1.0f);
}

}  // namespace
}  // namespace gltf_pbr
