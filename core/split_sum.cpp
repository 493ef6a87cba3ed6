// The split-sum integrals (see split_sum.hpp). No table is read here: preview/bake_tables.cpp
// compiles this file alone to bake the DFG table at build time.
#include "core/split_sum.hpp"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/brdf.hpp"

namespace gltf_pbr {
namespace {

float square(float x) { return x * x; }

}  // namespace

glm::vec3 importance_sample_ggx(glm::vec2 xi, float alpha) {
  const float phi = 2.0f * kPi * xi.y;
  const float cos_theta = std::sqrt((1.0f - xi.x) / (1.0f + (alpha * alpha - 1.0f) * xi.x));
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

glm::vec2 hammersley(std::uint32_t i, std::uint32_t n) {
  std::uint32_t bits = i;
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return {(static_cast<float>(i) + 0.5f) / static_cast<float>(n), static_cast<float>(bits) * 2.3283064365386963e-10f};
}

glm::vec2 integrate_dfg(float n_dot_v, float roughness, int samples) {
  n_dot_v = std::clamp(n_dot_v, 1e-4f, 1.0f);
  const float alpha = alpha_from_roughness(roughness);
  const glm::vec3 v(std::sqrt(1.0f - n_dot_v * n_dot_v), 0.0f, n_dot_v);
  glm::vec2 sum(0.0f);
  for (int i = 0; i < samples; ++i) {
    const glm::vec3 h =
        importance_sample_ggx(hammersley(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(samples)), alpha);
    const float v_dot_h = glm::dot(v, h);
    const glm::vec3 l = 2.0f * v_dot_h * h - v;
    const float n_dot_l = l.z;
    if (n_dot_l <= 0.0f || v_dot_h <= 0.0f) continue;
    // Estimator of the integral of D V (N.L) over L with pdf D (N.H) / (4 V.H) (Karis 2013, eq. 8).
    const float g_vis = visibility_smith_ggx_correlated(n_dot_v, n_dot_l, alpha) * 4.0f * n_dot_l * v_dot_h / h.z;
    const float fc = std::pow(1.0f - v_dot_h, 5.0f);
    sum += glm::vec2((1.0f - fc) * g_vis, fc * g_vis);
  }
  return sum / static_cast<float>(samples);
}

glm::vec2 dfg_table_cell(int row, int column) {
  return integrate_dfg(square((static_cast<float>(column) + 0.5f) / kDfgTableSize),
                       (static_cast<float>(row) + 0.5f) / kDfgTableSize, 2048);
}

}  // namespace gltf_pbr
