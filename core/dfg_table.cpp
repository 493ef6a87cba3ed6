// dfg_lookup (see split_sum.hpp) over the table baked at build time by preview/bake_tables.cpp.
#include <algorithm>
#include <cmath>
#include <glm/common.hpp>

#include "core/split_sum.hpp"

namespace gltf_pbr {

glm::vec2 dfg_lookup(float n_dot_v, float roughness) {
  // NaN reads as 0 (std::clamp passes NaN through, and a NaN index cast to int is undefined).
  auto unit = [](float x) { return x > 0.0f ? std::min(x, 1.0f) : 0.0f; };
  const float fx = std::sqrt(unit(n_dot_v)) * kDfgTableSize - 0.5f;
  const float fy = unit(roughness) * kDfgTableSize - 0.5f;
  const int x0 = std::clamp(static_cast<int>(fx + 1.0f) - 1, 0, kDfgTableSize - 1),
            x1 = std::min(x0 + 1, kDfgTableSize - 1);
  const int y0 = std::clamp(static_cast<int>(fy + 1.0f) - 1, 0, kDfgTableSize - 1),
            y1 = std::min(y0 + 1, kDfgTableSize - 1);
  const float tx = std::clamp(fx - static_cast<float>(x0), 0.0f, 1.0f),
              ty = std::clamp(fy - static_cast<float>(y0), 0.0f, 1.0f);
  auto at = [](int x, int y) {
    const float* cell = baked::kDfgTable + 2 * (y * kDfgTableSize + x);
    return glm::vec2(cell[0], cell[1]);
  };
  return glm::mix(glm::mix(at(x0, y0), at(x1, y0), tx), glm::mix(at(x0, y1), at(x1, y1), tx), ty);
}

}  // namespace gltf_pbr
