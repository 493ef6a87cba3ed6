// core/texel_buffer.hpp: a freed large buffer's pages serve the next buffers (in place, or moved
// into a larger one), and no more than the idle limit stays mapped.
#include "core/texel_buffer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace gltf_pbr {
namespace {

constexpr std::size_t kMiB = std::size_t{1} << 20;

// A buffer that takes every idle page there is (they are moved into it), so a test starts from none.
TexelBuffer<std::uint8_t> take_idle_pages() { return TexelBuffer<std::uint8_t>(idle_texel_bytes() + 2 * kMiB); }

TEST(TexelBuffer, AFreedLargeBufferIsTheNextOfItsSize) {
  const TexelPageReuse reuse;
  const auto held = take_idle_pages();
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

TEST(TexelBuffer, ALargerBufferTakesTheIdlePagesOfSmallerOnes) {
  const TexelPageReuse reuse;
  const auto held = take_idle_pages();
  {
    TexelBuffer<std::uint8_t> a(4 * kMiB), b(4 * kMiB);
    std::fill(a.begin(), a.end(), std::uint8_t{0xA1});
    std::fill(b.begin(), b.end(), std::uint8_t{0xB2});
  }
  ASSERT_EQ(idle_texel_bytes(), 8 * kMiB);
  // Not initialised (DefaultInitAllocator): what it holds are the pages moved in, then fresh ones.
  TexelBuffer<std::uint8_t> larger(12 * kMiB);
  EXPECT_EQ(idle_texel_bytes(), 0u);
  const std::size_t a_pages = static_cast<std::size_t>(std::count(larger.begin(), larger.end(), std::uint8_t{0xA1}));
  const std::size_t b_pages = static_cast<std::size_t>(std::count(larger.begin(), larger.end(), std::uint8_t{0xB2}));
  EXPECT_EQ(a_pages, 4 * kMiB);
  EXPECT_EQ(b_pages, 4 * kMiB);
  EXPECT_EQ(std::count(larger.begin() + 8 * kMiB, larger.end(), std::uint8_t{0}), static_cast<long>(4 * kMiB));
}

TEST(TexelBuffer, NoMoreThanTheLimitStaysIdle) {
  const TexelPageReuse reuse;
  {
    std::vector<TexelBuffer<std::uint8_t>> many;
    for (int i = 0; i < 40; ++i) many.emplace_back(10 * kMiB);  // 400 MiB freed at once below
  }
  EXPECT_LE(idle_texel_bytes(), kIdleTexelLimit);
  EXPECT_GT(idle_texel_bytes(), kIdleTexelLimit - 10 * kMiB);
  { TexelBuffer<std::uint8_t> beyond_the_limit(kIdleTexelLimit + 2 * kMiB); }
  EXPECT_LE(idle_texel_bytes(), kIdleTexelLimit);
  { TexelBuffer<std::uint8_t> small(kMiB); }  // malloc's, not kept here
  EXPECT_LE(idle_texel_bytes(), kIdleTexelLimit);
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
