// core/texel_buffer.hpp: inside a reuse scope a freed large buffer's pages serve the next buffer
// they hold, and no more than the idle limit stays mapped.
#include "core/texel_buffer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace gltf_pbr {
namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

TEST(TexelBuffer, AFreedLargeBufferIsTheNextOfItsSize) {
  const TexelPageReuse reuse;
  ASSERT_EQ(idle_texel_bytes(), 0u);
  const std::uint8_t* first = nullptr;
  {
    TexelBuffer<std::uint8_t> buffer(6 * kMiB);
    first = buffer.data();
  }
  EXPECT_EQ(idle_texel_bytes(), 6 * kMiB);
  TexelBuffer<std::uint8_t> again(6 * kMiB);
  EXPECT_EQ(again.data(), first);
  EXPECT_EQ(idle_texel_bytes(), 0u);
}

TEST(TexelBuffer, TheSmallestIdleRegionThatHoldsARequestServesItAndKeepsItsRest) {
  const TexelPageReuse reuse;
  const std::uint8_t *small_base = nullptr, *large_base = nullptr;
  {
    TexelBuffer<std::uint8_t> small(4 * kMiB), large(10 * kMiB);
    small_base = small.data(), large_base = large.data();
  }
  ASSERT_EQ(idle_texel_bytes(), 14 * kMiB);
  TexelBuffer<std::uint8_t> bigger_than_both(12 * kMiB);  // fresh pages: no one region holds it
  EXPECT_NE(bigger_than_both.data(), small_base);
  EXPECT_NE(bigger_than_both.data(), large_base);
  EXPECT_EQ(idle_texel_bytes(), 14 * kMiB);
  TexelBuffer<std::uint8_t> three(3 * kMiB);  // rounded to 4 MiB: the small region, not the large
  EXPECT_EQ(three.data(), small_base);
  TexelBuffer<std::uint8_t> six(6 * kMiB);  // the first 6 MiB of the large region; 4 stay idle
  EXPECT_EQ(six.data(), large_base);
  EXPECT_EQ(idle_texel_bytes(), 4 * kMiB);
  TexelBuffer<std::uint8_t> rest(4 * kMiB);
  EXPECT_EQ(rest.data(), large_base + 6 * kMiB);
  EXPECT_EQ(idle_texel_bytes(), 0u);
}

TEST(TexelBuffer, NoMoreThanTheLimitStaysIdle) {
  const TexelPageReuse reuse;
  {
    std::vector<TexelBuffer<std::uint8_t>> many;
    for (int i = 0; i < 40; ++i) many.emplace_back(10 * kMiB);  // 400 MiB freed at once below
  }
  const std::size_t idle = idle_texel_bytes();
  EXPECT_LE(idle, kIdleTexelLimit);
  EXPECT_GT(idle, kIdleTexelLimit - 10 * kMiB);
  { TexelBuffer<std::uint8_t> beyond_the_limit(kIdleTexelLimit + 2 * kMiB); }  // fresh, then unmapped
  EXPECT_EQ(idle_texel_bytes(), idle);
  { TexelBuffer<std::uint8_t> small(kMiB); }  // malloc's, not kept here
  EXPECT_EQ(idle_texel_bytes(), idle);
}

TEST(TexelBuffer, PagesAreKeptOnlyWhileAReuseScopeLives) {
  { TexelBuffer<std::uint8_t> unscoped(4 * kMiB); }
  EXPECT_EQ(idle_texel_bytes(), 0u);
  {
    const TexelPageReuse outer;
    {
      const TexelPageReuse inner;
      { TexelBuffer<std::uint8_t> scoped(4 * kMiB); }
      EXPECT_EQ(idle_texel_bytes(), 4 * kMiB);
    }
    EXPECT_EQ(idle_texel_bytes(), 4 * kMiB);  // the outer scope still lives
  }
  EXPECT_EQ(idle_texel_bytes(), 0u);
}

}  // namespace
}  // namespace gltf_pbr
