// LDR-FLIP (preview/flip.hpp): zero for identical images, the paper's colour metric alone on flat
// images, and feature errors concentrated where an edge moved.
#include "preview/flip.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace gltf_pbr::preview {
namespace {

std::vector<std::uint8_t> flat(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  std::vector<std::uint8_t> image;
  for (int i = 0; i < width * height; ++i) image.insert(image.end(), {r, g, b});
  return image;
}

// Black left of column `edge`, white from it.
std::vector<std::uint8_t> step(int width, int height, int edge) {
  std::vector<std::uint8_t> image;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image.insert(image.end(), 3, x < edge ? 0 : 255);
  return image;
}

TEST(Flip, IdenticalImagesHaveNoError) {
  std::mt19937 random(7);
  std::vector<std::uint8_t> noise(48 * 40 * 3);
  for (auto& value : noise) value = static_cast<std::uint8_t>(random());
  const FlipResult result = flip(noise, noise, 48, 40);
  ASSERT_EQ(result.per_pixel.size(), 48u * 40u);
  for (float error : result.per_pixel) EXPECT_EQ(error, 0.0f);
  EXPECT_EQ(result.mean, 0.0);
}

TEST(Flip, BlackAgainstWhiteIsNearlyTheLargestColourError) {
  // Flat images have no features, so the error is the colour term alone (section 4.1): HyAB of
  // Hunt-adjusted Lab, L 0 against 100, is 100; 100^0.7 = 25.12 lies above the knee 0.4·c_max,
  // c_max = HyAB(green, blue)^0.7 = 203.3^0.7 = 41.27, so the error is
  // 0.95 + (25.12 - 16.51) / (41.27 - 16.51) · 0.05 = 0.967.
  const FlipResult result = flip(flat(32, 32, 0, 0, 0), flat(32, 32, 255, 255, 255), 32, 32);
  EXPECT_NEAR(result.mean, 0.967, 0.002);
  for (float error : result.per_pixel) EXPECT_NEAR(error, result.mean, 1e-4);
}

TEST(Flip, SmallFlatColourChangesStayBelowTheKneeAndGrowWithTheChange) {
  const FlipResult near = flip(flat(16, 16, 120, 120, 120), flat(16, 16, 124, 120, 120), 16, 16);
  const FlipResult far = flip(flat(16, 16, 120, 120, 120), flat(16, 16, 160, 120, 120), 16, 16);
  EXPECT_GT(near.mean, 0.0);
  EXPECT_LT(near.mean, far.mean);
  EXPECT_LT(far.mean, 0.95);  // below the redistribution's knee output
}

TEST(Flip, AMovedEdgeIsAnErrorAtTheEdgeOnly) {
  const int width = 96, height = 24;
  const FlipResult result = flip(step(width, height, 48), step(width, height, 50), width, height);
  const int row = height / 2;
  auto at = [&](int x) { return result.per_pixel[static_cast<std::size_t>(row * width + x)]; };
  EXPECT_GT(at(49), 0.5f);
  EXPECT_LT(at(5), 1e-3f);
  EXPECT_LT(at(width - 6), 1e-3f);
  for (float error : result.per_pixel) {
    EXPECT_GE(error, 0.0f);
    EXPECT_LE(error, 1.0f);
  }
}

TEST(Flip, BandsOfAnySizeGiveTheWholeImageResultBitForBit) {
  // The filters' halo rows make a banded run the same sums in the same order as one band.
  const int width = 70, height = 61;
  std::mt19937 random(11);
  std::vector<std::uint8_t> a(static_cast<std::size_t>(width * height * 3)), b(a.size());
  for (auto& value : a) value = static_cast<std::uint8_t>(random());
  for (std::size_t i = 0; i < a.size(); ++i) b[i] = static_cast<std::uint8_t>(a[i] / 2 + (i % 97 == 0 ? 90 : 0));
  const FlipResult whole = flip(a, b, width, height, kFlipPixelsPerDegree, height);
  ASSERT_GT(whole.mean, 0.0);
  for (int band_rows : {1, 7, 20, 60}) {
    const FlipResult banded = flip(a, b, width, height, kFlipPixelsPerDegree, band_rows);
    EXPECT_EQ(banded.per_pixel, whole.per_pixel) << band_rows << " rows a band";
    EXPECT_DOUBLE_EQ(banded.mean, whole.mean) << band_rows << " rows a band";
  }
}

TEST(Flip, OnlyPixelsNearADifferenceHaveErrorAndTheyHaveTheirWholeImageValue) {
  // b differs from a in a 4 x 4 patch; c also in two far corners, so c's bands take other, wider
  // column windows. Near the patch both runs must agree bit for bit; past the filters' reach
  // (halo 10 at the default pixels per degree) b's error is exactly 0.
  const int width = 96, height = 80, halo = 10;
  std::mt19937 random(5);
  std::vector<std::uint8_t> a(static_cast<std::size_t>(width * height * 3));
  for (auto& value : a) value = static_cast<std::uint8_t>(random());
  auto at = [&](int x, int y) { return static_cast<std::size_t>(y * width + x); };
  std::vector<std::uint8_t> b = a;
  for (int y = 38; y < 42; ++y)
    for (int x = 46; x < 50; ++x) b[at(x, y) * 3] ^= 0x80;
  std::vector<std::uint8_t> c = b;
  c[at(0, 0) * 3 + 1] ^= 0x40;
  c[at(width - 1, height - 1) * 3 + 2] ^= 0x40;
  const FlipResult patch = flip(a, b, width, height), corners = flip(a, c, width, height);
  int compared = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int from_patch = std::max({46 - x, x - 49, 38 - y, y - 41, 0});
      const bool near_corner = std::max(x, y) <= 2 * halo || std::max(width - 1 - x, height - 1 - y) <= 2 * halo;
      if (from_patch > halo) {
        EXPECT_EQ(patch.per_pixel[at(x, y)], 0.0f) << x << ", " << y;
      }
      if (!near_corner) {
        ASSERT_EQ(patch.per_pixel[at(x, y)], corners.per_pixel[at(x, y)]) << x << ", " << y;
        ++compared;
      }
    }
  EXPECT_GT(patch.per_pixel[at(47, 39)], 0.1f);
  EXPECT_GT(compared, width * height / 2);
  EXPECT_GT(corners.mean, patch.mean);
}

}  // namespace
}  // namespace gltf_pbr::preview
