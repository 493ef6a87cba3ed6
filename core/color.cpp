#include "core/color.hpp"

#include <algorithm>
#include <cmath>

namespace gltf_pbr {

float srgb_to_linear(float encoded) {
  const float c = std::clamp(encoded, 0.0f, 1.0f);  // also maps NaN-free inputs only; callers check NaN
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

const std::array<float, 256>& srgb8_to_linear_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> linear{};
    for (int code = 0; code < 256; ++code)
      linear[static_cast<std::size_t>(code)] = srgb_to_linear(static_cast<float>(code) / 255.0f);
    return linear;
  }();
  return table;
}

float srgb8_to_linear(std::uint8_t code) { return srgb8_to_linear_table()[code]; }

glm::dvec3 linear_srgb_to_lab(glm::dvec3 rgb) {
  // IEC 61966-2-1 linear sRGB -> XYZ, normalised by the D65 white point.
  const double x = (0.4124564 * rgb.r + 0.3575761 * rgb.g + 0.1804375 * rgb.b) / 0.95047;
  const double y = (0.2126729 * rgb.r + 0.7151522 * rgb.g + 0.0721750 * rgb.b) / 1.00000;
  const double z = (0.0193339 * rgb.r + 0.1191920 * rgb.g + 0.9503041 * rgb.b) / 1.08883;
  // CIE 1976 L*a*b*: cube root with the linear segment below (6/29)^3.
  auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  return {116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))};
}

double delta_e_2000(glm::dvec3 lab1, glm::dvec3 lab2) {
  // Sharma, Wu, Dalal (2005), equations 1-22. The error statistics call this for every distinct
  // texel, so powers are products, hypot (its overflow care is not needed at Lab's magnitudes) is
  // a square root, and the four cosines of T (equation 15) come from one sine and cosine of the
  // mean hue by the angle-sum and multiple-angle identities.
  constexpr double pi = 3.14159265358979323846;
  constexpr double kPow25To7 = 6103515625.0;  // 25^7
  auto degrees = [](double radians) { return radians * 180.0 / pi; };
  auto radians = [](double deg) { return deg * pi / 180.0; };
  auto seventh = [](double x) {
    const double x2 = x * x;
    return x2 * x2 * x2 * x;
  };
  auto length = [](double a, double b) { return std::sqrt(a * a + b * b); };
  const double c1 = length(lab1.y, lab1.z), c2 = length(lab2.y, lab2.z);
  const double c_mean7 = seventh(0.5 * (c1 + c2));
  const double g = 0.5 * (1.0 - std::sqrt(c_mean7 / (c_mean7 + kPow25To7)));
  const double a1 = (1.0 + g) * lab1.y, a2 = (1.0 + g) * lab2.y;
  const double cp1 = length(a1, lab1.z), cp2 = length(a2, lab2.z);
  auto hue = [&](double b, double a) {
    if (a == 0.0 && b == 0.0) return 0.0;
    const double h = degrees(std::atan2(b, a));
    return h < 0.0 ? h + 360.0 : h;
  };
  const double hp1 = hue(lab1.z, a1), hp2 = hue(lab2.z, a2);
  const double dl = lab2.x - lab1.x, dc = cp2 - cp1;
  double dh = 0.0;
  if (cp1 * cp2 != 0.0) {
    dh = hp2 - hp1;
    if (dh > 180.0) dh -= 360.0;
    if (dh < -180.0) dh += 360.0;
  }
  const double dH = 2.0 * std::sqrt(cp1 * cp2) * std::sin(radians(dh / 2.0));
  const double l_mean = 0.5 * (lab1.x + lab2.x), cp_mean = 0.5 * (cp1 + cp2);
  double h_mean = hp1 + hp2;
  if (cp1 * cp2 != 0.0) {
    if (std::abs(hp1 - hp2) <= 180.0)
      h_mean /= 2.0;
    else
      h_mean = (hp1 + hp2 < 360.0) ? (hp1 + hp2 + 360.0) / 2.0 : (hp1 + hp2 - 360.0) / 2.0;
  }
  // T = 1 - 0.17 cos(h - 30°) + 0.24 cos(2h) + 0.32 cos(3h + 6°) - 0.20 cos(4h - 63°).
  const double ch = std::cos(radians(h_mean)), sh1 = std::sin(radians(h_mean));
  const double c2h = 2.0 * ch * ch - 1.0, s2h = 2.0 * sh1 * ch;
  const double c3h = ch * (4.0 * ch * ch - 3.0), s3h = sh1 * (3.0 - 4.0 * sh1 * sh1);
  const double c4h = 2.0 * c2h * c2h - 1.0, s4h = 2.0 * s2h * c2h;
  static const double cos30 = std::cos(radians(30.0)), sin30 = 0.5;
  static const double cos6 = std::cos(radians(6.0)), sin6 = std::sin(radians(6.0));
  static const double cos63 = std::cos(radians(63.0)), sin63 = std::sin(radians(63.0));
  const double t = 1.0 - 0.17 * (ch * cos30 + sh1 * sin30) + 0.24 * c2h + 0.32 * (c3h * cos6 - s3h * sin6) -
                   0.20 * (c4h * cos63 + s4h * sin63);
  const double theta_offset = (h_mean - 275.0) / 25.0;
  const double d_theta = 30.0 * std::exp(-theta_offset * theta_offset);
  const double cp_mean7 = seventh(cp_mean);
  const double rc = 2.0 * std::sqrt(cp_mean7 / (cp_mean7 + kPow25To7));
  const double l50 = (l_mean - 50.0) * (l_mean - 50.0);
  const double sl = 1.0 + 0.015 * l50 / std::sqrt(20.0 + l50);
  const double sc = 1.0 + 0.045 * cp_mean;
  const double sh = 1.0 + 0.015 * cp_mean * t;
  const double rt = -std::sin(radians(2.0 * d_theta)) * rc;
  const double tl = dl / sl, tc = dc / sc, th = dH / sh;
  return std::sqrt(tl * tl + tc * tc + th * th + rt * tc * th);
}

}  // namespace gltf_pbr
