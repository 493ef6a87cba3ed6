#include <gtest/gtest.h>

#include "core/color.hpp"

namespace gltf_pbr {
namespace {

// Test pairs from Sharma, Wu, Dalal (2005), Table 1.
TEST(DeltaE2000, MatchesSharmaReferenceData) {
  struct Pair { glm::dvec3 a, b; double expected; };
  const Pair pairs[] = {
      {{50.0, 2.6772, -79.7751}, {50.0, 0.0, -82.7485}, 2.0425},
      {{50.0, 3.1571, -77.2803}, {50.0, 0.0, -82.7485}, 2.8615},
      {{50.0, -1.3802, -84.2814}, {50.0, 0.0, -82.7485}, 1.0000},
      {{50.0, 2.5, 0.0}, {50.0, 0.0, -2.5}, 4.3065},
      {{50.0, 2.5, 0.0}, {73.0, 25.0, -18.0}, 27.1492},
      {{60.2574, -34.0099, 36.2677}, {60.4626, -34.1751, 39.4387}, 1.2644},
      {{22.7233, 20.0904, -46.6940}, {23.0331, 14.9730, -42.5619}, 2.0373},
      {{2.0776, 0.0795, -1.1350}, {0.9033, -0.0636, -0.5514}, 0.9082},
  };
  for (const Pair& p : pairs) {
    EXPECT_NEAR(delta_e_2000(p.a, p.b), p.expected, 1e-4);
    EXPECT_NEAR(delta_e_2000(p.b, p.a), p.expected, 1e-4) << "ΔE2000 is symmetric";
  }
}

TEST(DeltaE2000, IsZeroForIdenticalColours) {
  for (double v : {0.0, 0.04, 0.5, 1.0})
    EXPECT_EQ(delta_e_2000(linear_srgb_to_lab({v, v * 0.5, v}), linear_srgb_to_lab({v, v * 0.5, v})), 0.0);
}

TEST(Lab, WhiteIsL100AndBlackIsL0) {
  const glm::dvec3 white = linear_srgb_to_lab({1, 1, 1}), black = linear_srgb_to_lab({0, 0, 0});
  EXPECT_NEAR(white.x, 100.0, 1e-3);
  EXPECT_NEAR(white.y, 0.0, 1e-3);
  EXPECT_NEAR(white.z, 0.0, 1e-3);
  EXPECT_NEAR(black.x, 0.0, 1e-9);
}

TEST(Srgb, RoundTripsEvery8BitValue) {
  for (int i = 0; i < 256; ++i) {
    const float encoded = static_cast<float>(i) / 255.0f;
    EXPECT_NEAR(linear_to_srgb(srgb_to_linear(encoded)), encoded, 1e-5f) << i;
  }
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.21404f, 1e-5f);  // IEC 61966-2-1
}

}  // namespace
}  // namespace gltf_pbr
