#include <gtest/gtest.h>

#include <cmath>
#include <random>

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

// Sharma, Wu, Dalal (2005) equations 1-22 written out as the paper gives them (pow, hypot, four
// cosines): the scalar reference for the rearranged arithmetic in core/color.cpp.
double delta_e_2000_as_written(glm::dvec3 lab1, glm::dvec3 lab2) {
  constexpr double pi = 3.14159265358979323846;
  auto degrees = [](double radians) { return radians * 180.0 / pi; };
  auto radians = [](double deg) { return deg * pi / 180.0; };
  const double c_mean = 0.5 * (std::hypot(lab1.y, lab1.z) + std::hypot(lab2.y, lab2.z));
  const double g = 0.5 * (1.0 - std::sqrt(std::pow(c_mean, 7.0) / (std::pow(c_mean, 7.0) + std::pow(25.0, 7.0))));
  const double a1 = (1.0 + g) * lab1.y, a2 = (1.0 + g) * lab2.y;
  const double cp1 = std::hypot(a1, lab1.z), cp2 = std::hypot(a2, lab2.z);
  auto hue = [&](double b, double a) {
    if (a == 0.0 && b == 0.0) return 0.0;
    const double h = degrees(std::atan2(b, a));
    return h < 0.0 ? h + 360.0 : h;
  };
  const double hp1 = hue(lab1.z, a1), hp2 = hue(lab2.z, a2);
  double dh = 0.0;
  if (cp1 * cp2 != 0.0) {
    dh = hp2 - hp1;
    if (dh > 180.0) dh -= 360.0;
    if (dh < -180.0) dh += 360.0;
  }
  const double dH = 2.0 * std::sqrt(cp1 * cp2) * std::sin(radians(dh / 2.0));
  const double l_mean = 0.5 * (lab1.x + lab2.x), cp_mean = 0.5 * (cp1 + cp2);
  double h_mean = hp1 + hp2;
  if (cp1 * cp2 != 0.0)
    h_mean = std::abs(hp1 - hp2) <= 180.0 ? h_mean / 2.0
             : hp1 + hp2 < 360.0          ? (hp1 + hp2 + 360.0) / 2.0
                                          : (hp1 + hp2 - 360.0) / 2.0;
  const double t = 1.0 - 0.17 * std::cos(radians(h_mean - 30.0)) + 0.24 * std::cos(radians(2.0 * h_mean)) +
                   0.32 * std::cos(radians(3.0 * h_mean + 6.0)) - 0.20 * std::cos(radians(4.0 * h_mean - 63.0));
  const double d_theta = 30.0 * std::exp(-std::pow((h_mean - 275.0) / 25.0, 2.0));
  const double rc = 2.0 * std::sqrt(std::pow(cp_mean, 7.0) / (std::pow(cp_mean, 7.0) + std::pow(25.0, 7.0)));
  const double l50 = (l_mean - 50.0) * (l_mean - 50.0);
  const double sl = 1.0 + 0.015 * l50 / std::sqrt(20.0 + l50), sc = 1.0 + 0.045 * cp_mean;
  const double sh = 1.0 + 0.015 * cp_mean * t, rt = -std::sin(radians(2.0 * d_theta)) * rc;
  const double tl = (lab2.x - lab1.x) / sl, tc = (cp2 - cp1) / sc, th = dH / sh;
  return std::sqrt(tl * tl + tc * tc + th * th + rt * tc * th);
}

TEST(DeltaE2000, AgreesWithTheEquationsAsWrittenOnRandomPairs) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> lightness(0.0, 100.0), chroma(-128.0, 128.0);
  for (int i = 0; i < 200000; ++i) {
    const glm::dvec3 a(lightness(random), chroma(random), chroma(random));
    // Near pairs too: the conversion's errors are mostly small.
    const glm::dvec3 b = i % 2 ? glm::dvec3(lightness(random), chroma(random), chroma(random))
                               : a + 0.02 * glm::dvec3(chroma(random), chroma(random), chroma(random));
    const double expected = delta_e_2000_as_written(a, b);
    ASSERT_NEAR(delta_e_2000(a, b), expected, 1e-9 * (1.0 + expected)) << i;
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
