// core/texel_buffer.hpp: inside a reuse scope a freed large buffer's pages serve the next buffer
// they hold, and no more than the idle limit stays mapped.
#include "core/texel_buffer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
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
  std::optional<TexelBuffer<std::uint8_t>> small(std::in_place, 4 * kMiB);
  const TexelBuffer<std::uint8_t> between(2 * kMiB);  // kept: the two freed regions do not touch
  std::optional<TexelBuffer<std::uint8_t>> large(std::in_place, 10 * kMiB);
  const std::uint8_t *small_base = small->data(), *large_base = large->data();
  small.reset(), large.reset();
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

// Idle regions that touch are one region: a conversion's freed 4, 4 and 12 MiB maps, lying end
// to end, hold a render's 16 MiB visibility buffer. (Here the three come out of one freed 20 MiB
// buffer, so they touch whatever the kernel's placement of new mappings.)
TEST(TexelBuffer, IdleRegionsThatTouchServeABufferNoneOfThemHoldsAlone) {
  const TexelPageReuse reuse;
  const std::uint8_t* start = nullptr;
  { start = TexelBuffer<std::uint8_t>(20 * kMiB).data(); }
  ASSERT_EQ(idle_texel_bytes(), 20 * kMiB);
  std::optional<TexelBuffer<std::uint8_t>> a(std::in_place, 4 * kMiB), b(std::in_place, 4 * kMiB),
      c(std::in_place, 12 * kMiB);
  ASSERT_EQ(a->data(), start);  // each from the front of what is left
  ASSERT_EQ(b->data(), start + 4 * kMiB);
  ASSERT_EQ(c->data(), start + 8 * kMiB);
  ASSERT_EQ(idle_texel_bytes(), 0u);
  a.reset(), c.reset();
  EXPECT_EQ(idle_texel_bytes(), 16 * kMiB);
  const TexelBuffer<std::uint8_t> neither(14 * kMiB);  // a and c do not touch: fresh pages
  EXPECT_EQ(idle_texel_bytes(), 16 * kMiB);
  b.reset();  // joins the regions on both sides
  TexelBuffer<std::uint8_t> visibility(18 * kMiB);
  EXPECT_EQ(visibility.data(), start);
  EXPECT_EQ(idle_texel_bytes(), 2 * kMiB);
  std::fill(visibility.begin(), visibility.end(), std::uint8_t{1});
  EXPECT_EQ(visibility[4 * kMiB - 1] + visibility[4 * kMiB] + visibility[8 * kMiB], 3);
}

// A full list of idle regions refuses a freed buffer that touches none of them, and still takes
// one that joins them (the list does not grow).
TEST(TexelBuffer, AFullIdleListStillJoinsAFreedNeighbour) {
  const TexelPageReuse reuse;
  std::vector<TexelBuffer<std::uint8_t>> kept, freed;
  const std::uint8_t* start = nullptr;
  { start = TexelBuffer<std::uint8_t>(256 * kMiB).data(); }  // 128 buffers of 2 MiB from here
  for (int i = 0; i < 64; ++i) kept.emplace_back(2 * kMiB), freed.emplace_back(2 * kMiB);
  ASSERT_EQ(kept.front().data(), start);
  ASSERT_EQ(freed.back().data(), start + 254 * kMiB);
  ASSERT_EQ(idle_texel_bytes(), 0u);
  freed.clear();  // 64 idle regions, a kept buffer between each two
  ASSERT_EQ(idle_texel_bytes(), 128 * kMiB);
  { TexelBuffer<std::uint8_t> apart(4 * kMiB); }  // no region holds it; freed, it touches none: unmapped
  EXPECT_EQ(idle_texel_bytes(), 128 * kMiB);
  kept.erase(kept.begin());  // the lowest touches one idle region: joined while the list is full
  EXPECT_EQ(idle_texel_bytes(), 130 * kMiB);
  kept.pop_back();  // touches the two idle regions around it
  EXPECT_EQ(idle_texel_bytes(), 132 * kMiB);
  TexelBuffer<std::uint8_t> joined(6 * kMiB);  // only those three together hold it
  EXPECT_EQ(joined.data(), start + 250 * kMiB);
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
