#include "converter/solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <vector>

namespace gltf_pbr {
namespace {

constexpr float kDielectricF0 = 0.04f;                      // glTF 2.0 Appendix B, ior 1.5
constexpr float kDielectricDiffuse = 1.0f - kDielectricF0;  // (1 - F) at normal incidence
constexpr float kDarkestMetalF0 = 0.45f;                    // Unity material validator; Hoffman's table

// The metric: CIELAB linearised at each target colour (Gauss-Newton on CIE 1976 L*a*b*). Around
// a target t, a small linear-RGB error r moves Lab by J r, with
//   J = A · diag(f'(x), f'(y), f'(z)) · M,
// M the linear sRGB to XYZ matrix (IEC 61966-2-1, D65) with each row divided by the white point,
// f'(u) = (1/3) u^(-2/3) the slope of CIELAB's cube root (CIE 15:2004, 8.2.1) and A the rows
// L* = 116 fy, a* = 500 (fx - fy), b* = 200 (fy - fz). |J r|^2 is then a squared ΔE. A
// per-channel weight cannot see chroma: it fitted Box's grey F0 0.2 over a red diffuse with a
// red-tinted metal (29 ΔE2000 on F0, against 24 for leaving F0 a grey 0.04).
// eps in (u + eps) keeps black finite and stands for the flare of a real view.
constexpr float kWeightEpsilon = 0.05f;
// CIE94 and CIEDE2000 count chroma and hue differences 1 / (1 + 0.045 C*) of the mean chroma of
// the pair. Linearised at the target alone that overstates the compression whenever the fit is
// less saturated than the target (Box's red diffuse turned brown), so it is applied more gently.
// Tuned on the shared assets' ΔE2000 (bench/RESULTS.md) and the sweeps in tests/solver_test.cpp.
constexpr float kChromaCompression = 0.01f;
// Prior weight on metalness, in ΔE^2 per unit m^2. With black diffuse the fit has two basins (a
// dielectric at m = 0 and a dark metal at m = 1, base = F0) and its minimiser jumps between them
// as the specular rises; the prior's curvature must beat the fit's there. With a bright diffuse
// there is no ambiguity, and a weak prior lets the fit decide. Tuned on sweeps of specular
// 0..1.1 in steps of 0.001 and 2000 random materials (tests/solver_test.cpp).
constexpr float kPriorWeightOnBlack = 5000.0f;
constexpr float kPriorWeightOnBright = 50.0f;
constexpr float kBrightDiffuse = 0.2f;  // diffuse weight from which the weak prior applies
// Where the fit has two basins of near-equal error (a legacy material whose diffuse and specular
// hues disagree), the lowest one switches abruptly as the inputs move. Minima within this width
// of the lowest share the answer instead (see solve): relative to the lowest error, plus 1 ΔE^2.
constexpr float kBlendWidthRelative = 0.5f;
constexpr float kBlendWidthAbsolute = 1.0f;

float max3(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

float smoothstep01(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// (u + eps)^(-2/3) / 3, from a table with linear interpolation on [0, 2] (continuous, and six pow
// calls a texel were a third of the solve time), exact beyond.
float cube_root_slope(float u) {
  constexpr int kSize = 4096;
  constexpr float kRange = 2.0f;
  static const std::vector<float> table = [] {
    std::vector<float> v(kSize + 1);
    for (int i = 0; i <= kSize; ++i)
      v[static_cast<size_t>(i)] =
          std::pow(kRange * static_cast<float>(i) / kSize + kWeightEpsilon, -2.0f / 3.0f) / 3.0f;
    return v;
  }();
  u = std::max(u, 0.0f);
  if (!(u < kRange)) return std::pow(u + kWeightEpsilon, -2.0f / 3.0f) / 3.0f;
  const float x = u * (kSize / kRange);
  const size_t i = static_cast<size_t>(x);
  const float f = x - static_cast<float>(i);
  return table[i] + f * (table[i + 1] - table[i]);
}

// Q = JᵀJ for the target t: |J r|^2 = rᵀ Q r, the squared ΔE of a linear-RGB error r near t.
glm::mat3 lab_metric(glm::vec3 t) {
  // glm matrices are column-major; these are written row by row and transposed.
  static const glm::mat3 kToXyzOverWhite = glm::transpose(glm::mat3(  //
      0.4124f / 0.95047f, 0.3576f / 0.95047f, 0.1805f / 0.95047f,     //
      0.2126f, 0.7152f, 0.0722f,                                      //
      0.0193f / 1.08883f, 0.1192f / 1.08883f, 0.9505f / 1.08883f));
  static const glm::mat3 kLabRows = glm::transpose(glm::mat3(0.0f, 116.0f, 0.0f,     //
                                                             500.0f, -500.0f, 0.0f,  //
                                                             0.0f, 200.0f, -200.0f));
  const glm::vec3 xyz = kToXyzOverWhite * t;
  glm::mat3 slope(0.0f);
  for (int c = 0; c < 3; ++c) slope[c][c] = cube_root_slope(xyz[c]);
  glm::mat3 jacobian = kLabRows * slope * kToXyzOverWhite;
  const glm::vec3 f(std::cbrt(xyz.x + kWeightEpsilon), std::cbrt(xyz.y + kWeightEpsilon),
                    std::cbrt(xyz.z + kWeightEpsilon));
  const float chroma = std::hypot(500.0f * (f.x - f.y), 200.0f * (f.y - f.z));
  const float compression = 1.0f / (1.0f + kChromaCompression * chroma);
  for (int column = 0; column < 3; ++column) jacobian[column][1] *= compression, jacobian[column][2] *= compression;
  return glm::transpose(jacobian) * jacobian;
}

float quadratic_form(const glm::mat3& q, glm::vec3 r) { return glm::dot(r, q * r); }

// What one solve minimises, fixed for all m: targets, their metrics and the prior.
struct Objective {
  Reflectance target;
  glm::mat3 diffuse_metric, f0_metric;               // Qd, Qf
  glm::vec3 diffuse_pull, f0_pull, dielectric_pull;  // Qd D, Qf F, Qf (1, 1, 1)
  float prior_m, prior_weight;
};

Objective objective_for(const SpecGloss& legacy) {
  Objective o;
  o.target = legacy_reflectance(legacy, LegacyReading::A);
  o.diffuse_metric = lab_metric(o.target.diffuse);
  o.f0_metric = lab_metric(o.target.f0);
  o.diffuse_pull = o.diffuse_metric * o.target.diffuse;
  o.f0_pull = o.f0_metric * o.target.f0;
  o.dielectric_pull = o.f0_metric * glm::vec3(1.0f);
  const float mean_f0 = (o.target.f0.x + o.target.f0.y + o.target.f0.z) / 3.0f;
  o.prior_m = smoothstep01((mean_f0 - kDielectricF0) / (kDarkestMetalF0 - kDielectricF0));
  o.prior_weight = kPriorWeightOnBright + (kPriorWeightOnBlack - kPriorWeightOnBright) *
                                              (1.0f - smoothstep01(max3(o.target.diffuse) / kBrightDiffuse));
  return o;
}

// min over b >= 0 of ½ bᵀHb − gᵀb for a positive definite 3×3 H: active-set iteration on the
// KKT conditions (the free channels solve their reduced system; a channel held at 0 is freed
// when its gradient (H b − g) turns negative). Three channels settle in a few rounds.
glm::vec3 nonnegative_minimiser(const glm::mat3& h, glm::vec3 g) {
  bool held[3] = {false, false, false};
  glm::vec3 b(0.0f);
  for (int round = 0; round < 8; ++round) {
    int free[3], n = 0;
    for (int c = 0; c < 3; ++c)
      if (!held[c]) free[n++] = c;
    b = glm::vec3(0.0f);
    if (n == 3) {
      b = glm::inverse(h) * g;
    } else if (n == 2) {
      const int i = free[0], j = free[1];
      const float det = h[i][i] * h[j][j] - h[i][j] * h[i][j];
      b[i] = (h[j][j] * g[i] - h[i][j] * g[j]) / det;
      b[j] = (h[i][i] * g[j] - h[i][j] * g[i]) / det;
    } else if (n == 1) {
      b[free[0]] = g[free[0]] / h[free[0]][free[0]];
    }
    bool changed = false;
    for (int c = 0; c < 3; ++c)
      if (!held[c] && b[c] < 0.0f) held[c] = true, changed = true;
    if (changed) continue;
    const glm::vec3 gradient = h * b - g;
    for (int c = 0; c < 3; ++c)
      if (held[c] && gradient[c] < 0.0f) held[c] = false, changed = true;
    if (!changed) break;
  }
  return glm::max(b, glm::vec3(0.0f));
}

// The base for metalness m: the best non-negative base for
//   |Jd (k (1-m) b - D)|^2 + |Jf (0.04 (1-m) + m b - F)|^2,   k = 0.96,
// whose normal equations are H b = g with
//   H = k^2 (1-m)^2 Qd + m^2 Qf,   g = k (1-m) Qd D + m Qf (F - 0.04 (1-m)),
// then brought into [0, 1] by scaling the whole colour when a channel exceeds 1 (a saturated
// diffuse of 1.0 needs 1/0.96; gold's red F0 is 1.022). Clipping that channel alone would shift
// the hue; the scale is 1 at the gamut edge, so the result stays continuous. Qd and Qf are
// positive definite (J is a product of invertible matrices) and the two scales are never both 0
// on [0, 1], so H is invertible: no epsilon is needed.
glm::vec3 base_at(float m, const Objective& o) {
  const float k = kDielectricDiffuse, one_minus = 1.0f - m;
  const glm::mat3 h = (k * k * one_minus * one_minus) * o.diffuse_metric + (m * m) * o.f0_metric;
  const glm::vec3 g =
      (k * one_minus) * o.diffuse_pull + m * (o.f0_pull - kDielectricF0 * one_minus * o.dielectric_pull);
  const glm::vec3 base = nonnegative_minimiser(h, g);
  const float largest = max3(base);
  return largest > 1.0f ? base / largest : base;
}

// The objective at m, for the base that m is given.
float error_at(float m, const Objective& o) {
  const float k = kDielectricDiffuse, one_minus = 1.0f - m;
  const glm::vec3 b = base_at(m, o);
  const glm::vec3 diffuse_error = (k * one_minus) * b - o.target.diffuse;
  const glm::vec3 f0_error = glm::vec3(kDielectricF0 * one_minus) + m * b - o.target.f0;
  return quadratic_form(o.diffuse_metric, diffuse_error) + quadratic_form(o.f0_metric, f0_error) +
         o.prior_weight * (m - o.prior_m) * (m - o.prior_m);
}

struct Minimum {
  float m, error, prominence;
};

// Golden-section search in [lo, hi] from a sampled minimum (m, error).
Minimum refine(float lo, float hi, float m, float error, int iterations, const Objective& objective) {
  constexpr float kInvPhi = 0.6180339887f;
  float x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
  float e1 = error_at(x1, objective), e2 = error_at(x2, objective);
  for (int i = 0; i < iterations; ++i) {
    if (e1 < e2) {
      hi = x2, x2 = x1, e2 = e1;
      x1 = hi - kInvPhi * (hi - lo), e1 = error_at(x1, objective);
    } else {
      lo = x1, x1 = x2, e1 = e2;
      x2 = lo + kInvPhi * (hi - lo), e2 = error_at(x2, objective);
    }
  }
  if (iterations > 0) {
    if (e1 < error) error = e1, m = x1;
    if (e2 < error) error = e2, m = x2;
  }
  return {m, error, 0.0f};
}

// The local minima of the sampled errors, refined, each with its prominence: how far it lies
// below the highest sample between it and the nearest other minimum (infinite with none).
std::vector<Minimum> local_minima(const std::vector<float>& samples, int refine_iterations, const Objective& o) {
  const int last = static_cast<int>(samples.size()) - 1;
  const auto sample = [&](int i) { return samples[static_cast<size_t>(i)]; };
  std::vector<int> at;
  for (int i = 0; i <= last; ++i)
    if ((i == 0 || sample(i) <= sample(i - 1)) && (i == last || sample(i) < sample(i + 1))) at.push_back(i);
  const auto highest_between = [&](int from, int to) {
    float highest = sample(from);
    for (int i = from + 1; i <= to; ++i) highest = std::max(highest, sample(i));
    return highest;
  };
  const float step = 1.0f / static_cast<float>(std::max(1, last));
  std::vector<Minimum> minima;
  for (size_t j = 0; j < at.size(); ++j) {
    const int i = at[j];
    const float m = static_cast<float>(i) * step;
    Minimum found = refine(std::max(0.0f, m - step), std::min(1.0f, m + step), m, sample(i), refine_iterations, o);
    float barrier = std::numeric_limits<float>::infinity();
    if (j > 0) barrier = std::min(barrier, highest_between(at[j - 1], i));
    if (j + 1 < at.size()) barrier = std::min(barrier, highest_between(i, at[j + 1]));
    found.prominence = barrier - found.error;
    minima.push_back(found);
  }
  return minima;
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

  // Coarse grid over m, then golden-section search around each local minimum of the samples.
  const int steps = std::max(1, settings.grid_steps);
  std::vector<float> samples(static_cast<size_t>(steps) + 1);
  for (int i = 0; i <= steps; ++i)
    samples[static_cast<size_t>(i)] = error_at(static_cast<float>(i) / static_cast<float>(steps), objective);
  const std::vector<Minimum> minima = local_minima(samples, settings.refine_iterations, objective);

  // Minima within the blend width of the lowest share the answer, weighted by how close they
  // come to it and by how prominent they are. As the inputs move, a minimum's weight falls
  // smoothly to 0 as its error rises above the lowest or as it flattens out and vanishes, so m
  // moves continuously where a plain argmin jumps. One clear minimum, the usual case, keeps its
  // m exactly.
  float lowest = std::numeric_limits<float>::infinity(), lowest_m = 0.0f;
  for (const Minimum& minimum : minima)
    if (minimum.error < lowest) lowest = minimum.error, lowest_m = minimum.m;
  const float width = kBlendWidthRelative * lowest + kBlendWidthAbsolute;
  float weight_sum = 0.0f, weighted_m = 0.0f;
  for (const Minimum& minimum : minima) {
    const float weight =
        std::max(0.0f, 1.0f - (minimum.error - lowest) / width) * std::min(1.0f, minimum.prominence / width);
    weight_sum += weight, weighted_m += weight * minimum.m;
  }
  const float m = weight_sum > 0.0f ? weighted_m / weight_sum : lowest_m;
  return {base_at(m, objective), m, std::clamp(1.0f - legacy.glossiness, 0.0f, 1.0f)};
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
