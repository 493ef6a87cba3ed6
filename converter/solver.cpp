#include "converter/solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/common.hpp>
#include <vector>

namespace gltf_pbr {
namespace {

constexpr float kDielectricF0 = 0.04f;                      // glTF 2.0 Appendix B, ior 1.5
constexpr float kDielectricDiffuse = 1.0f - kDielectricF0;  // (1 - F) at normal incidence
constexpr float kDarkestMetalF0 = 0.45f;                    // Unity material validator; Hoffman's table

// Perceptual weighting: ΔE2000 follows L*, which grows as Y^(1/3), so a reflectance error dY at
// level Y costs about dY * Y^(-2/3); squared, the residual's weight is (Y + eps)^(-4/3)
// (Gauss-Newton on CIE 1976 L*). eps keeps black finite and stands for the flare of a real view.
constexpr float kWeightEpsilon = 0.05f;
// Prior weight. With black diffuse the fit has two basins (a dielectric at m = 0 and a dark metal
// at m = 1, base = F0) and its minimiser jumps between them as the specular rises; the prior's
// curvature must beat the fit's there. With a bright diffuse there is no ambiguity, and a weak
// prior lets the fit decide. Tuned on sweeps of specular 0..1.1 in steps of 0.001 and 2000 random
// materials (tests/solver_test.cpp): largest metalness step 0.009, mean second-pass drift 0.8 ΔE.
constexpr float kPriorWeightOnBlack = 10.0f;
constexpr float kPriorWeightOnBright = 0.1f;
constexpr float kBrightDiffuse = 0.2f;  // diffuse weight from which the weak prior applies

float max3(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

float smoothstep01(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// What one solve minimises, fixed for all m: targets, their weights and the prior.
struct Objective {
  Reflectance target;
  glm::vec3 diffuse_weight, f0_weight;
  float prior_m, prior_weight;
};

// (t + eps)^(-4/3), from a table with linear interpolation on [0, 2] (continuous, and six pow
// calls a texel were a third of the solve time), exact beyond.
float perceptual_weight(float t) {
  constexpr int kSize = 4096;
  constexpr float kRange = 2.0f;
  static const std::vector<float> table = [] {
    std::vector<float> v(kSize + 1);
    for (int i = 0; i <= kSize; ++i)
      v[static_cast<size_t>(i)] = std::pow(kRange * static_cast<float>(i) / kSize + kWeightEpsilon, -4.0f / 3.0f);
    return v;
  }();
  t = std::max(t, 0.0f);
  if (!(t < kRange)) return std::pow(t + kWeightEpsilon, -4.0f / 3.0f);
  const float x = t * (kSize / kRange);
  const size_t i = static_cast<size_t>(x);
  const float f = x - static_cast<float>(i);
  return table[i] + f * (table[i + 1] - table[i]);
}

Objective objective_for(const SpecGloss& legacy) {
  Objective o;
  o.target = legacy_reflectance(legacy, LegacyReading::A);
  for (int c = 0; c < 3; ++c) {
    o.diffuse_weight[c] = perceptual_weight(o.target.diffuse[c]);
    o.f0_weight[c] = perceptual_weight(o.target.f0[c]);
  }
  const float mean_f0 = (o.target.f0.x + o.target.f0.y + o.target.f0.z) / 3.0f;
  o.prior_m = smoothstep01((mean_f0 - kDielectricF0) / (kDarkestMetalF0 - kDielectricF0));
  o.prior_weight = kPriorWeightOnBright + (kPriorWeightOnBlack - kPriorWeightOnBright) *
                                              (1.0f - smoothstep01(max3(o.target.diffuse) / kBrightDiffuse));
  return o;
}

struct Fit {
  glm::vec3 base;
  float error;
};

// Best base for a fixed metalness m: per channel, minimise
//   wd (k b (1-m) - D)^2 + wf (0.04 (1-m) + b m - F)^2,   k = 0.96,
// a convex quadratic in b whose minimiser, clamped to [0, 1], is exact:
//   b = (wd k (1-m) D + wf m (F - 0.04 (1-m))) / (wd k^2 (1-m)^2 + wf m^2).
// The denominator is at least min(wd, wf) k^2/(1+k^2) > 0 on [0, 1]: no epsilon is needed.
Fit fit_at(float m, const Objective& o) {
  const float k = kDielectricDiffuse, one_minus = 1.0f - m;
  Fit fit{{}, o.prior_weight * (m - o.prior_m) * (m - o.prior_m)};
  for (int c = 0; c < 3; ++c) {
    const float d = o.target.diffuse[c], f = o.target.f0[c], wd = o.diffuse_weight[c], wf = o.f0_weight[c];
    const float b = std::clamp((wd * k * one_minus * d + wf * m * (f - kDielectricF0 * one_minus)) /
                                   (wd * k * k * one_minus * one_minus + wf * m * m),
                               0.0f, 1.0f);
    const float diffuse_error = k * b * one_minus - d;
    const float f0_error = kDielectricF0 * one_minus + b * m - f;
    fit.base[c] = b;
    fit.error += wd * diffuse_error * diffuse_error + wf * f0_error * f0_error;
  }
  return fit;
}

// The final base for metalness m: the unclamped per-channel fit, brought into [0, 1] by scaling
// the whole colour when a channel exceeds 1 (a saturated diffuse of 1.0 needs 1/0.96; gold's red
// F0 is 1.022). Clipping that channel alone would shift the hue, which ΔE2000 weighs more than the
// same loss spread evenly; the scale is 1 at the gamut edge, so the result stays continuous.
glm::vec3 in_gamut_base(float m, const Objective& o) {
  const float k = kDielectricDiffuse, one_minus = 1.0f - m;
  glm::vec3 base;
  for (int c = 0; c < 3; ++c) {
    const float d = o.target.diffuse[c], f = o.target.f0[c], wd = o.diffuse_weight[c], wf = o.f0_weight[c];
    base[c] = std::max(0.0f, (wd * k * one_minus * d + wf * m * (f - kDielectricF0 * one_minus)) /
                                 (wd * k * k * one_minus * one_minus + wf * m * m));
  }
  const float largest = max3(base);
  return largest > 1.0f ? base / largest : base;
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
  const Objective objective = objective_for(legacy);

  // Coarse grid over m, then golden-section search in the bracket around the best sample.
  const int steps = std::max(1, settings.grid_steps);
  float best_m = 0.0f;
  Fit best = fit_at(0.0f, objective);
  for (int i = 1; i <= steps; ++i) {
    const float m = static_cast<float>(i) / static_cast<float>(steps);
    const Fit fit = fit_at(m, objective);
    if (fit.error < best.error) best = fit, best_m = m;
  }
  float lo = std::max(0.0f, best_m - 1.0f / static_cast<float>(steps));
  float hi = std::min(1.0f, best_m + 1.0f / static_cast<float>(steps));
  constexpr float kInvPhi = 0.6180339887f;
  float x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
  Fit f1 = fit_at(x1, objective), f2 = fit_at(x2, objective);
  for (int i = 0; i < settings.refine_iterations; ++i) {
    if (f1.error < f2.error) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - kInvPhi * (hi - lo), f1 = fit_at(x1, objective);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + kInvPhi * (hi - lo), f2 = fit_at(x2, objective);
    }
  }
  if (settings.refine_iterations > 0) {
    if (f1.error < best.error) best = f1, best_m = x1;
    if (f2.error < best.error) best = f2, best_m = x2;
  }
  return {in_gamut_base(best_m, objective), best_m, std::clamp(1.0f - legacy.glossiness, 0.0f, 1.0f)};
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
