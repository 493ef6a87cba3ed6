// Small scalar helpers for the per-pixel passes.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/brdf.hpp"  // kPi

namespace gltf_pbr::preview {

// floor without a libm call: x86-64's baseline SSE2 has no rounding instruction (roundss is
// SSE4.1), so std::floor compiles to a call into libm, several per pixel in texel and map
// look-ups. Truncation, corrected below zero, is exact wherever a float has a fractional part
// (|x| < 2^23); larger magnitudes are integers already, and NaN passes through.
inline float floor_fast(float x) {
  if (!(std::abs(x) < 8388608.0f)) return x;
  const float truncated = static_cast<float>(static_cast<int>(x));
  return truncated > x ? truncated - 1.0f : truncated;
}

// atan2 to ~1e-5 rad (minimax polynomial on [0, 1]; Abramowitz & Stegun 4.4.49 style): a
// thousandth of a texel of the 256-wide map, at a fraction of libm's cost per pixel.
inline float fast_atan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float largest = std::max(ax, ay);
  if (!(largest > 0.0f)) return 0.0f;
  const float a = std::min(ax, ay) / largest, s = a * a;
  float r = ((-0.0464964749f * s + 0.15931422f) * s - 0.327622764f) * s * a + a;
  if (ay > ax) r = 0.5f * kPi - r;
  if (x < 0.0f) r = kPi - r;
  return y < 0.0f ? -r : r;
}

// acos to 7e-5 rad (Abramowitz & Stegun 4.4.45).
inline float fast_acos(float x) {
  const float ax = std::min(std::abs(x), 1.0f);
  const float r = std::sqrt(1.0f - ax) * (((-0.0187293f * ax + 0.0742610f) * ax - 0.2121144f) * ax + 1.5707288f);
  return x < 0.0f ? kPi - r : r;
}

}  // namespace gltf_pbr::preview
