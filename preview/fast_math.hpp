// Small scalar helpers for the per-pixel passes.
#pragma once
#include <cmath>

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

}  // namespace gltf_pbr::preview
