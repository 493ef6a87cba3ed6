#include "converter/solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/common.hpp>

namespace gltf_pbr {
namespace {

constexpr float kDielectricF0 = 0.04f;                  // glTF 2.0 Appendix B, ior 1.5
constexpr float kDielectricDiffuse = 1.0f - kDielectricF0;  // (1 - F) at normal incidence
constexpr float kDarkestMetalF0 = 0.45f;                // Unity material validator; Hoffman's table
// Weight of the prior. With black diffuse the fit alone has two basins (dielectric m = 0 and a
// dark metal m = 1, base = F0) and its minimiser jumps between them as the specular rises; the
// prior's curvature must exceed the fit's negative curvature there. Measured over a sweep of
// specular 0..1 in steps of 0.001 (tests/solver_test.cpp): lambda = 0.01 jumps by 0.76 in m,
// 0.1 by 0.49, 0.3 moves at most 0.017 per step. Larger values cost fit error (mean diffuse ΔE
// 5.4 -> 6.1 at lambda = 1 over the shared assets' materials and random samples).
constexpr float kPriorWeight = 0.3f;

float max3(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

float smoothstep01(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

struct Fit {
  glm::vec3 base;
  float error;
};

// Best base for a fixed metalness m: per channel, minimise
//   (k b (1-m) - D)^2 + (0.04 (1-m) + b m - F)^2,   k = 0.96,
// whose unconstrained minimiser is b = (k (1-m) D + m (F - 0.04 (1-m))) / (k^2 (1-m)^2 + m^2).
// The denominator is at least k^2/(1+k^2) > 0.47 on [0, 1], so no epsilon is needed.
Fit fit_at(float m, const Reflectance& target, float m_prior) {
  const float k = kDielectricDiffuse, one_minus = 1.0f - m;
  const float denominator = k * k * one_minus * one_minus + m * m;
  Fit fit{{}, kPriorWeight * (m - m_prior) * (m - m_prior)};
  for (int c = 0; c < 3; ++c) {
    const float d = target.diffuse[c], f = target.f0[c];
    const float b = std::clamp((k * one_minus * d + m * (f - kDielectricF0 * one_minus)) / denominator, 0.0f, 1.0f);
    const float diffuse_error = k * b * one_minus - d;
    const float f0_error = kDielectricF0 * one_minus + b * m - f;
    fit.base[c] = b;
    fit.error += diffuse_error * diffuse_error + f0_error * f0_error;
  }
  return fit;
}

}  // namespace

Reflectance legacy_reflectance(const SpecGloss& legacy, LegacyReading reading) {
  // Archived KHR_materials_pbrSpecularGlossiness: c_diff = diffuse * (1 - max(specular)).
  // A specular above 1 (gold) must not make the diffuse weight negative.
  const float diffuse_scale = std::max(0.0f, 1.0f - max3(legacy.specular));
  Reflectance r{legacy.diffuse * diffuse_scale, legacy.specular};
  if (reading == LegacyReading::B) r.diffuse *= glm::clamp(1.0f - legacy.specular, 0.0f, 1.0f);
  return r;
}

Reflectance core_reflectance(const MetalRough& core) {
  const float m = core.metalness;
  return {core.base * (1.0f - m) * kDielectricDiffuse, glm::mix(glm::vec3(kDielectricF0), core.base, m)};
}

Reflectance specular_extension_reflectance(glm::vec3 base, glm::vec3 f0) {
  // KHR_materials_specular: the dielectric diffuse is scaled by 1 - max(F0) at normal incidence.
  return {base * std::max(0.0f, 1.0f - max3(f0)), f0};
}

SolverSettings solver_preset(const char* name) {
  if (std::strcmp(name, "fast") == 0) return {8, 0};
  if (std::strcmp(name, "exact") == 0) return {64, 40};
  if (std::strcmp(name, "reference") == 0) return {0, 0, true};
  return {};
}

MetalRough solve(const SpecGloss& legacy, const SolverSettings& settings) {
  if (settings.reference_formula) return solve_reference(legacy);
  const Reflectance target = legacy_reflectance(legacy, LegacyReading::A);
  const float mean_f0 = (target.f0.x + target.f0.y + target.f0.z) / 3.0f;
  const float m_prior = smoothstep01((mean_f0 - kDielectricF0) / (kDarkestMetalF0 - kDielectricF0));

  // Coarse grid over m, then golden-section search in the bracket around the best sample.
  const int steps = std::max(1, settings.grid_steps);
  float best_m = 0.0f;
  Fit best = fit_at(0.0f, target, m_prior);
  for (int i = 1; i <= steps; ++i) {
    const float m = static_cast<float>(i) / static_cast<float>(steps);
    const Fit fit = fit_at(m, target, m_prior);
    if (fit.error < best.error) best = fit, best_m = m;
  }
  float lo = std::max(0.0f, best_m - 1.0f / static_cast<float>(steps));
  float hi = std::min(1.0f, best_m + 1.0f / static_cast<float>(steps));
  constexpr float kInvPhi = 0.6180339887f;
  float x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
  Fit f1 = fit_at(x1, target, m_prior), f2 = fit_at(x2, target, m_prior);
  for (int i = 0; i < settings.refine_iterations; ++i) {
    if (f1.error < f2.error) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - kInvPhi * (hi - lo), f1 = fit_at(x1, target, m_prior);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + kInvPhi * (hi - lo), f2 = fit_at(x2, target, m_prior);
    }
  }
  if (settings.refine_iterations > 0) {
    if (f1.error < best.error) best = f1, best_m = x1;
    if (f2.error < best.error) best = f2, best_m = x2;
  }
  return {best.base, best_m, std::clamp(1.0f - legacy.glossiness, 0.0f, 1.0f)};
}

MetalRough solve_reference(const SpecGloss& legacy) {
  // Archived KHR_materials_pbrSpecularGlossiness examples / glTF-SDK PBRUtils::SpecularToMetallic.
  constexpr float kEpsilon = 1e-6f;
  auto brightness = [](glm::vec3 c) { return std::sqrt(0.299f * c.r * c.r + 0.587f * c.g * c.g + 0.114f * c.b * c.b); };
  const glm::vec3 specular = glm::clamp(legacy.specular, 0.0f, 1.0f);
  const float one_minus_specular = 1.0f - max3(specular);
  const float diffuse = brightness(legacy.diffuse), spec = brightness(specular);
  float metalness = 0.0f;
  if (spec >= kDielectricF0) {
    const float a = kDielectricF0;
    const float b = diffuse * one_minus_specular / (1.0f - kDielectricF0) + spec - 2.0f * kDielectricF0;
    const float c = kDielectricF0 - spec;
    const float d = std::max(b * b - 4.0f * a * c, 0.0f);
    metalness = std::clamp((-b + std::sqrt(d)) / (2.0f * a), 0.0f, 1.0f);
  }
  const glm::vec3 from_diffuse =
      legacy.diffuse * (one_minus_specular / (1.0f - kDielectricF0) / std::max(1.0f - metalness, kEpsilon));
  const glm::vec3 from_specular =
      (specular - kDielectricF0 * (1.0f - metalness)) * (1.0f / std::max(metalness, kEpsilon));
  const glm::vec3 base = glm::mix(from_diffuse, from_specular, metalness * metalness);
  return {glm::clamp(base, 0.0f, 1.0f), metalness, std::clamp(1.0f - legacy.glossiness, 0.0f, 1.0f)};
}

SpecGloss to_spec_gloss(const MetalRough& core) {
  const Reflectance r = core_reflectance(core);
  const float diffuse_scale = 1.0f - max3(r.f0);
  SpecGloss legacy;
  legacy.specular = r.f0;
  legacy.diffuse = diffuse_scale > 0.0f ? glm::clamp(r.diffuse / diffuse_scale, 0.0f, 1.0f) : glm::vec3(0.0f);
  legacy.glossiness = 1.0f - core.roughness;
  return legacy;
}

}  // namespace gltf_pbr
