#include "core/color.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/vec2.hpp>
#include <limits>
#include <random>
#include <span>
#include <vector>

namespace gltf_pbr {
namespace {

// Test pairs from Sharma, Wu, Dalal (2005), Table 1.
TEST(DeltaE2000, MatchesSharmaReferenceData) {
  struct Pair {
    glm::dvec3 a, b;
    double expected;
  };
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

// The batch forms (float SIMD lanes) against the double-precision scalar functions.
std::vector<glm::vec3> lab_batch_of(const std::vector<glm::vec3>& linear) {
  std::vector<glm::vec3> lab(linear.size());
  linear_srgb_to_lab(linear, lab);
  return lab;
}

std::vector<float> delta_e_batch_of(const std::vector<glm::vec3>& lab1, const std::vector<glm::vec3>& lab2) {
  std::vector<float> delta_e(lab1.size());
  delta_e_2000(lab1, lab2, delta_e);
  return delta_e;
}

TEST(DeltaE2000Batch, MatchesSharmaReferenceData) {
  // Sharma, Wu, Dalal (2005), Table 1: all 34 pairs, which probe every branch of the hue mean,
  // hue difference and the achromatic cases.
  const double table[][7] = {
      {50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425},
      {50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615},
      {50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412},
      {50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000},
      {50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000},
      {50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000},
      {50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669},
      {50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669},
      {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792},
      {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792},
      {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195},
      {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195},
      {50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045},
      {50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045},
      {50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461},
      {50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065},
      {50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492},
      {50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977},
      {50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030},
      {50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535},
      {50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000},
      {50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000},
      {50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000},
      {50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000},
      {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644},
      {63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630},
      {61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731},
      {35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645},
      {22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373},
      {36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146},
      {90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441},
      {90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381},
      {6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377},
      {2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082},
  };
  std::vector<glm::vec3> lab1, lab2;
  for (const auto& row : table) {
    lab1.emplace_back(row[0], row[1], row[2]);
    lab2.emplace_back(row[3], row[4], row[5]);
  }
  const std::vector<float> forward = delta_e_batch_of(lab1, lab2), backward = delta_e_batch_of(lab2, lab1);
  for (size_t i = 0; i < std::size(table); ++i) {
    // Float inputs and arithmetic: Sharma's four decimals hold to 2e-4.
    EXPECT_NEAR(forward[i], table[i][6], 2e-4) << "pair " << i + 1;
    EXPECT_NEAR(backward[i], table[i][6], 2e-4) << "pair " << i + 1 << " reversed";
  }
}

TEST(DeltaE2000Batch, AgreesWithTheScalarFunctionOnRandomAndEdgePairs) {
  std::mt19937 random(11);
  std::uniform_real_distribution<float> lightness(0.0f, 100.0f), chroma(-128.0f, 128.0f), unit(-1.0f, 1.0f);
  std::vector<glm::vec3> lab1, lab2;
  for (int i = 0; i < 200000; ++i) {
    const glm::vec3 a(lightness(random), chroma(random), chroma(random));
    lab1.push_back(a);
    switch (i % 5) {
      case 0:
        lab2.emplace_back(lightness(random), chroma(random), chroma(random));
        break;
      case 1:
        lab2.push_back(a + 0.02f * glm::vec3(chroma(random), chroma(random), chroma(random)));
        break;
      case 2:
        lab2.push_back(a);
        break;   // identical: 0
      case 3: {  // hues nearly opposite: 180° ± 0.5-2° apart, either side of equation 10's branch
        // (at exactly 180° the formula itself jumps, and float and double may fall either side)
        const float turn =
            3.14159265f + (unit(random) < 0 ? -1.0f : 1.0f) * (0.0087f + 0.026f * std::abs(unit(random)));
        lab2.emplace_back(a.x, a.y * std::cos(turn) - a.z * std::sin(turn),
                          a.y * std::sin(turn) + a.z * std::cos(turn));
        break;
      }
      default:
        lab2.emplace_back(lightness(random), 1e-3f * unit(random), 0.0f);
        break;  // near grey
    }
  }
  for (float l : {0.0f, 50.0f, 100.0f})  // achromatic pairs and hue angles on the axes
    for (glm::vec2 ab : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(0, 1), glm::vec2(-1, 0), glm::vec2(0, -1)})
      for (glm::vec2 cd : {glm::vec2(0, 0), glm::vec2(-3, 0), glm::vec2(0, -3), glm::vec2(2, 2)})
        lab1.emplace_back(l, ab.x, ab.y), lab2.emplace_back(100.0f - l, cd.x, cd.y);
  const std::vector<float> batch = delta_e_batch_of(lab1, lab2);
  double worst = 0.0;
  for (size_t i = 0; i < lab1.size(); ++i) {
    const double expected = delta_e_2000(glm::dvec3(lab1[i]), glm::dvec3(lab2[i]));
    ASSERT_TRUE(std::isfinite(batch[i])) << i;
    worst = std::max(worst, std::abs(batch[i] - expected) / (1.0 + expected));
  }
  // Float rounding through equations 1-22: a few parts in 10^5 of 1 + ΔE.
  EXPECT_LT(worst, 5e-5) << "ΔE2000 in float lanes against double, relative to 1 + ΔE";
}

TEST(DeltaE2000Batch, ALanesAnswerDoesNotDependOnItsNeighbours) {
  std::mt19937 random(5);
  std::uniform_real_distribution<float> lightness(0.0f, 100.0f), chroma(-100.0f, 100.0f);
  std::vector<glm::vec3> lab1, lab2;
  for (int i = 0; i < 101; ++i) {  // not a multiple of the lane count: the last batch is short
    lab1.emplace_back(lightness(random), chroma(random), chroma(random));
    lab2.emplace_back(lightness(random), chroma(random), chroma(random));
  }
  const std::vector<float> together = delta_e_batch_of(lab1, lab2);
  for (size_t i = 0; i < lab1.size(); ++i) {
    float alone = -1.0f;
    delta_e_2000(std::span(&lab1[i], 1), std::span(&lab2[i], 1), std::span(&alone, 1));
    EXPECT_EQ(alone, together[i]) << i;
  }
}

TEST(LabBatch, AgreesWithTheScalarConversionFromBlackToBeyondWhite) {
  std::vector<glm::vec3> linear;
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 100000; ++i) linear.emplace_back(unit(random), unit(random), unit(random));
  // Black, the cube root's linear segment and its joint, white, and an F0 above 1.
  for (float v : {0.0f, 1e-6f, 0.002f, 216.0f / 24389.0f, 0.009f, 0.04f, 1.0f, 1.3f, 4.0f})
    linear.emplace_back(v, v, v), linear.emplace_back(v, 0.0f, 0.5f * v);
  const std::vector<glm::vec3> lab = lab_batch_of(linear);
  for (size_t i = 0; i < linear.size(); ++i) {
    const glm::dvec3 expected = linear_srgb_to_lab(glm::dvec3(linear[i]));
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(lab[i][c], expected[c], 2e-4 * (1.0 + std::abs(expected[c]))) << i << " channel " << c;
  }
}

TEST(DeltaE2000Batch, IsZeroForIdenticalColours) {
  const std::vector<glm::vec3> linear = {{0, 0, 0}, {0.04f, 0.02f, 0.04f}, {0.5f, 0.25f, 0.5f}, {1, 1, 1}};
  const std::vector<glm::vec3> lab = lab_batch_of(linear);
  for (float d : delta_e_batch_of(lab, lab)) EXPECT_EQ(d, 0.0f);
}

TEST(DeltaE2000Batch, ANaNColourGivesNaNNotAPerfectMatch) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<glm::vec3> lab = lab_batch_of({{nan, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}});
  EXPECT_TRUE(std::isnan(lab[0].x)) << "L* of a NaN colour";
  const std::vector<float> delta_e = delta_e_batch_of({lab[0], {50, 0, 0}, {nan, nan, nan}}, {lab[1], lab[1], lab[1]});
  EXPECT_TRUE(std::isnan(delta_e[0]));
  EXPECT_FALSE(std::isnan(delta_e[1])) << "a NaN lane leaves its neighbours alone";
  EXPECT_TRUE(std::isnan(delta_e[2]));
}

}  // namespace
}  // namespace gltf_pbr
