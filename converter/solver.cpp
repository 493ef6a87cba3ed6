#include "converter/solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>
#include <limits>
#include <mutex>
#include <span>
#include <vector>

#include "core/lanes.hpp"
#include "core/split_sum.hpp"

namespace gltf_pbr {
namespace {

constexpr float kDielectricDiffuse = 1.0f - kDielectricF0;  // (1 - F) at normal incidence

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

float roughness_of(const SpecGloss& legacy) { return std::clamp(1.0f - legacy.glossiness, 0.0f, 1.0f); }

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
  // (u + eps)^(1/3) = 3 (u + eps) · slope(u): the cube roots come from the slopes already looked up.
  glm::vec3 f;
  for (int c = 0; c < 3; ++c) f[c] = 3.0f * (xyz[c] + kWeightEpsilon) * slope[c][c];
  const float a = 500.0f * (f.x - f.y), b = 200.0f * (f.y - f.z);
  const float chroma = std::sqrt(a * a + b * b);
  const float compression = 1.0f / (1.0f + kChromaCompression * chroma);
  for (int column = 0; column < 3; ++column) jacobian[column][1] *= compression, jacobian[column][2] *= compression;
  return glm::transpose(jacobian) * jacobian;
}

float quadratic_form(const glm::mat3& q, glm::vec3 r) { return glm::dot(r, q * r); }

// The split-sum terms (A, B) of the appearance model's rings (solver.hpp) at a roughness: a table
// over roughness in kRoughnessSteps steps, linear between, each row integrated on first use (a
// factor-only material needs two of them, not the 65).
constexpr int kRoughnessSteps = 64;
constexpr int kDfgSamples = 1024;
struct RingSplitSums {
  glm::vec2 ring[kAppearanceRings];  // (A, B)
};
RingSplitSums ring_split_sums(float roughness) {
  static std::once_flag filled[kRoughnessSteps + 1];
  static RingSplitSums rows[kRoughnessSteps + 1];
  const auto row = [](int i) -> const RingSplitSums& {
    std::call_once(filled[i], [i] {
      for (int k = 0; k < kAppearanceRings; ++k)
        rows[i].ring[k] =
            integrate_dfg(appearance_ring_cosine(k), static_cast<float>(i) / kRoughnessSteps, kDfgSamples);
    });
    return rows[i];
  };
  const float x = (roughness > 0.0f ? std::min(roughness, 1.0f) : 0.0f) * kRoughnessSteps;  // NaN: 0
  const int i = std::min(static_cast<int>(x), kRoughnessSteps - 1);
  const float f = x - static_cast<float>(i);
  const RingSplitSums &lo = row(i), &hi = row(i + 1);
  RingSplitSums out;
  for (int k = 0; k < kAppearanceRings; ++k) out.ring[k] = lo.ring[k] + f * (hi.ring[k] - lo.ring[k]);
  return out;
}

// The dielectric layer's (1 - F) over the hemisphere at a ring: w = 1 - (0.04 A + B).
float dielectric_transmission(glm::vec2 split_sum) { return 1.0f - (kDielectricF0 * split_sum.x + split_sum.y); }

// One term of the objective (solver.hpp): the core quantity a(m) b + c(m) (1, 1, 1) against the
// legacy target, a(m) = a0 + m a1, c(m) = c0 + m c1, in the metric of the target.
struct Term {
  float a0, a1, c0, c1, weight;
  glm::vec3 target;
};
constexpr int kMaxTerms = 2 * kAppearanceRings;
// A legacy radiance above this (a specular far above 1, which no material has) enters the fit
// scaled down to it, hue kept: no core material reaches past about 1 anyway, and the squared
// residuals of 1e30 would overflow.
constexpr float kBrightestTarget = 4.0f;
glm::vec3 bounded(glm::vec3 target) {
  const float largest = max3(target);
  return largest > kBrightestTarget ? target * (kBrightestTarget / largest) : target;
}

// The terms of `model` for one legacy material: the same numbers solve() and the lanes use.
int terms_of(const SpecGloss& legacy, ErrorModel model, Term* terms) {
  const Reflectance r = legacy_reflectance(legacy, LegacyReading::A);
  if (model == ErrorModel::NormalIncidence) {
    terms[0] = {kDielectricDiffuse, -kDielectricDiffuse, 0.0f, 0.0f, 1.0f, r.diffuse};
    terms[1] = {0.0f, 1.0f, kDielectricF0, -kDielectricF0, 1.0f, r.f0};
    return 2;
  }
  const RingSplitSums split = ring_split_sums(roughness_of(legacy));
  const Appearance seen = legacy_appearance(legacy);
  constexpr float kWeight = 1.0f / kAppearanceRings;
  for (int k = 0; k < kAppearanceRings; ++k) {
    const glm::vec2 ab = split.ring[k];
    const float w = dielectric_transmission(ab);
    // Under the uniform light: diffuse and specular together.
    const float lit = kAppearanceDiffuseLight * w;
    terms[2 * k] = {lit,     ab.x - lit,           kDielectricF0 * ab.x + ab.y, -kDielectricF0 * ab.x,
                    kWeight, bounded(seen.ring[k])};
    // What reflects the environment's detail: the specular lobe alone.
    terms[2 * k + 1] = {0.0f,
                        ab.x,
                        kDielectricF0 * ab.x + ab.y,
                        -kDielectricF0 * ab.x,
                        kWeight,
                        bounded(legacy.specular * ab.x + ab.y)};
  }
  return 2 * kAppearanceRings;
}

// What one solve minimises, fixed for all m: the terms with their metrics, the normal equations
// as polynomials in m (H(m) = h[0] + m h[1] + m^2 h[2], likewise g), and the prior.
struct Objective {
  int terms = 0;
  Term term[kMaxTerms];
  glm::mat3 metric[kMaxTerms];                 // weight J^T J of each term's target
  glm::vec3 pull[kMaxTerms], grey[kMaxTerms];  // metric T and metric (1, 1, 1)
  glm::mat3 h[3];
  glm::vec3 g[3];
  float prior_m, prior_weight;
};

// `previous`, when given, is another input's objective whose metrics are reused where a target
// is the same colour: the same numbers, and a texture with a specular factor (most of them) has
// one F0 for every texel.
Objective objective_for(const SpecGloss& legacy, ErrorModel model, const Objective* previous = nullptr) {
  Objective o;
  o.terms = terms_of(legacy, model, o.term);
  for (int i = 0; i < 3; ++i) o.h[i] = glm::mat3(0.0f), o.g[i] = glm::vec3(0.0f);
  for (int t = 0; t < o.terms; ++t) {
    const Term& term = o.term[t];
    const bool same = previous && previous->terms == o.terms && previous->term[t].target == term.target &&
                      previous->term[t].weight == term.weight;
    if (same) {
      o.metric[t] = previous->metric[t], o.pull[t] = previous->pull[t], o.grey[t] = previous->grey[t];
    } else {
      o.metric[t] = term.weight * lab_metric(term.target);
      o.pull[t] = o.metric[t] * term.target, o.grey[t] = o.metric[t] * glm::vec3(1.0f);
    }
    const glm::mat3& q = o.metric[t];
    const glm::vec3 pull = o.pull[t], grey_pull = o.grey[t];
    // sum (a0 + m a1)^2 Q and sum (a0 + m a1) Q (T - (c0 + m c1) 1), expanded in m. The
    // normal-incidence terms have a0 = 0 or c = 0: what they leave out costs nothing.
    if (term.a0 != 0.0f) {
      o.h[0] += (term.a0 * term.a0) * q, o.h[1] += (2.0f * term.a0 * term.a1) * q;
      o.g[0] += term.a0 * (pull - term.c0 * grey_pull);
    }
    o.h[2] += (term.a1 * term.a1) * q;
    o.g[1] += term.a1 * (pull - term.c0 * grey_pull);
    if (term.c1 != 0.0f) o.g[1] -= (term.a0 * term.c1) * grey_pull, o.g[2] -= (term.a1 * term.c1) * grey_pull;
  }
  const float mean_f0 = (legacy.specular.x + legacy.specular.y + legacy.specular.z) / 3.0f;
  const Reflectance r = legacy_reflectance(legacy, LegacyReading::A);
  o.prior_m = metal_likeness(mean_f0);
  o.prior_weight = kPriorWeightOnBright + (kPriorWeightOnBlack - kPriorWeightOnBright) *
                                              (1.0f - smoothstep01(max3(r.diffuse) / kBrightDiffuse));
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

// The base for metalness m: the best non-negative base for the terms at m, whose normal
// equations are H(m) b = g(m), then brought into [0, 1] by scaling the whole colour when a channel
// exceeds 1 (a saturated diffuse of 1.0 needs 1/0.96; gold's red F0 is 1.022). Clipping that
// channel alone would shift the hue; the scale is 1 at the gamut edge, so the result stays
// continuous. Each metric is positive definite (J is a product of invertible matrices) and the
// terms' scales a(m) never all vanish on [0, 1], so H is invertible: no epsilon is needed.
glm::vec3 base_at(float m, const Objective& o) {
  const glm::mat3 h = o.h[0] + m * o.h[1] + (m * m) * o.h[2];
  const glm::vec3 g = o.g[0] + m * o.g[1] + (m * m) * o.g[2];
  const glm::vec3 base = nonnegative_minimiser(h, g);
  const float largest = max3(base);
  return largest > 1.0f ? base / largest : base;
}

// The objective at m, for the base that m is given: each term's residual in its metric.
float error_at(float m, const Objective& o) {
  const glm::vec3 b = base_at(m, o);
  float error = o.prior_weight * (m - o.prior_m) * (m - o.prior_m);
  for (int t = 0; t < o.terms; ++t) {
    const Term& term = o.term[t];
    const glm::vec3 residual = (term.a0 + m * term.a1) * b + glm::vec3(term.c0 + m * term.c1) - term.target;
    error += quadratic_form(o.metric[t], residual);
  }
  return error;
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

// The indices of the local minima of the sampled errors (the lowest of a flat run), written to
// `at` (room for samples.size() / 2 + 1); returns how many.
size_t sampled_minima(std::span<const float> samples, std::span<int> at) {
  const int last = static_cast<int>(samples.size()) - 1;
  const auto sample = [&](int i) { return samples[static_cast<size_t>(i)]; };
  size_t found = 0;
  for (int i = 0; i <= last; ++i)
    if ((i == 0 || sample(i) <= sample(i - 1)) && (i == last || sample(i) < sample(i + 1))) at[found++] = i;
  return found;
}

// The bracket a sampled minimum is refined in: one grid step either side, within [0, 1].
struct Bracket {
  float lo, hi, m;
};
Bracket bracket_of(int i, size_t samples) {
  const float step = 1.0f / static_cast<float>(std::max<size_t>(1, samples - 1));
  const float m = static_cast<float>(i) * step;
  return {std::max(0.0f, m - step), std::min(1.0f, m + step), m};
}

// How far minimum j (refined to `error`) lies below the highest sample between it and the
// nearest other minimum: infinite with none.
float prominence(std::span<const float> samples, std::span<const int> at, size_t j, float error) {
  const auto highest_between = [&](int from, int to) {
    return *std::max_element(samples.begin() + from, samples.begin() + to + 1);
  };
  float barrier = std::numeric_limits<float>::infinity();
  if (j > 0) barrier = std::min(barrier, highest_between(at[j - 1], at[j]));
  if (j + 1 < at.size()) barrier = std::min(barrier, highest_between(at[j], at[j + 1]));
  return barrier - error;
}

// The local minima of the sampled errors, refined, each with its prominence.
std::vector<Minimum> local_minima(const std::vector<float>& samples, int refine_iterations, const Objective& o) {
  std::vector<int> at(samples.size() / 2 + 1);
  at.resize(sampled_minima(samples, at));
  std::vector<Minimum> minima;
  for (size_t j = 0; j < at.size(); ++j) {
    const Bracket b = bracket_of(at[j], samples.size());
    Minimum found = refine(b.lo, b.hi, b.m, samples[static_cast<size_t>(at[j])], refine_iterations, o);
    found.prominence = prominence(samples, at, j, found.error);
    minima.push_back(found);
  }
  return minima;
}

// Minima within the blend width of the lowest share the answer, weighted by how close they come
// to it and by how prominent they are. As the inputs move, a minimum's weight falls smoothly to 0
// as its error rises above the lowest or as it flattens out and vanishes, so m moves continuously
// where a plain argmin jumps. One clear minimum, the usual case, keeps its m exactly.
float blended_metalness(std::span<const Minimum> minima) {
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
  return weight_sum > 0.0f ? weighted_m / weight_sum : lowest_m;
}

// The batch solver: kLanes solves side by side in SIMD lanes (GCC/Clang vector extensions; each
// lane is an independent solve, so a lane's answer never depends on its neighbours). Same
// objective, grid, refinement and blending as solve(); the 3×3 systems are solved by cofactors
// rather than glm::inverse, so results agree with solve() to float rounding, not bit for bit.
// The rare lane whose unconstrained base has a negative channel takes the scalar active set.
namespace lane_solver {

using namespace lanes;
constexpr int kMaxGrid = 64;  // the "exact" preset's; finer grids take the scalar solve

// A symmetric 3×3 matrix per lane: xx, yy, zz, xy, xz, yz.
struct Symmetric {
  Floats e[6];
};
struct Vec {
  Floats c[3];
};

// What solve() builds per input, as structure of arrays. Every lane has the same number of terms
// (the error model is the batch's).
struct Objectives {
  int terms;
  Floats a0[kMaxTerms], a1[kMaxTerms], c0[kMaxTerms], c1[kMaxTerms];
  Vec target[kMaxTerms];
  Symmetric metric[kMaxTerms], h[3];
  Vec g[3];
  Floats prior_m, prior_weight;
};

GLTF_PBR_INLINE Floats quadratic_form(const Symmetric& q, const Vec& r) {
  const Floats x = r.c[0], y = r.c[1], z = r.c[2];
  return q.e[0] * x * x + q.e[1] * y * y + q.e[2] * z * z + 2.0f * (q.e[3] * x * y + q.e[4] * x * z + q.e[5] * y * z);
}

// nonnegative_minimiser() of the lanes in `todo`, whose unconstrained minimiser `b` has a negative
// channel. For a positive definite H the constrained minimiser is the one point that meets the
// KKT conditions: the free channels solve their reduced system and are >= 0, and the gradient
// H b - g of each channel held at 0 is >= 0. The lanes try the free sets in turn (two channels,
// one, none) and keep the first that meets them; a lane that rounding leaves without one takes
// the scalar active set.
GLTF_PBR_INLINE Vec nonnegative_minimiser(const Symmetric& h, const Vec& g, Vec b, Mask todo) {
  static constexpr int kIndex[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
  const auto at = [&](int i, int j) { return h.e[kIndex[i][j]]; };
  const auto take = [&](Mask ok, const Floats(&candidate)[3]) {
    const Mask now = todo & ok;
    for (int c = 0; c < 3; ++c) b.c[c] = select(now, candidate[c], b.c[c]);
    todo &= ~now;
  };
  for (int k = 0; k < 3 && any(todo); ++k) {  // free i and j, k held
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const Floats inverse_det = 1.0f / (at(i, i) * at(j, j) - at(i, j) * at(i, j));
    Floats candidate[3];
    candidate[i] = (at(j, j) * g.c[i] - at(i, j) * g.c[j]) * inverse_det;
    candidate[j] = (at(i, i) * g.c[j] - at(i, j) * g.c[i]) * inverse_det;
    candidate[k] = splat(0.0f);
    take((candidate[i] >= 0.0f) & (candidate[j] >= 0.0f) &
             (at(k, i) * candidate[i] + at(k, j) * candidate[j] - g.c[k] >= 0.0f),
         candidate);
  }
  for (int i = 0; i < 3 && any(todo); ++i) {  // free i alone
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    Floats candidate[3];
    candidate[i] = g.c[i] / at(i, i);
    candidate[j] = candidate[k] = splat(0.0f);
    take((candidate[i] >= 0.0f) & (at(j, i) * candidate[i] - g.c[j] >= 0.0f) &
             (at(k, i) * candidate[i] - g.c[k] >= 0.0f),
         candidate);
  }
  if (any(todo)) {  // all held: the gradient -g must be >= 0
    const Floats zero[3] = {splat(0.0f), splat(0.0f), splat(0.0f)};
    take((g.c[0] <= 0.0f) & (g.c[1] <= 0.0f) & (g.c[2] <= 0.0f), zero);
  }
  for (int l = 0; l < kLanes; ++l) {
    if (!todo[l]) continue;
    const glm::mat3 hl(at(0, 0)[l], at(1, 0)[l], at(2, 0)[l], at(0, 1)[l], at(1, 1)[l], at(2, 1)[l], at(0, 2)[l],
                       at(1, 2)[l], at(2, 2)[l]);
    const glm::vec3 bl = gltf_pbr::nonnegative_minimiser(hl, glm::vec3(g.c[0][l], g.c[1][l], g.c[2][l]));
    for (int c = 0; c < 3; ++c) b.c[c][l] = bl[c];
  }
  return b;
}

// base_at() of every lane.
GLTF_PBR_INLINE Vec base_at(Floats m, const Objectives& o) {
  const Floats m2 = m * m;
  Symmetric h;
  for (int i = 0; i < 6; ++i) h.e[i] = o.h[0].e[i] + m * o.h[1].e[i] + m2 * o.h[2].e[i];
  Vec g;
  for (int i = 0; i < 3; ++i) g.c[i] = o.g[0].c[i] + m * o.g[1].c[i] + m2 * o.g[2].c[i];
  // H⁻¹ g by cofactors (H is symmetric, so is its adjugate).
  const Floats xx = h.e[0], yy = h.e[1], zz = h.e[2], xy = h.e[3], xz = h.e[4], yz = h.e[5];
  const Floats c00 = yy * zz - yz * yz, c01 = xz * yz - xy * zz, c02 = xy * yz - xz * yy;
  const Floats c11 = xx * zz - xz * xz, c12 = xy * xz - xx * yz, c22 = xx * yy - xy * xy;
  const Floats inverse_det = 1.0f / (xx * c00 + xy * c01 + xz * c02);
  Vec b;
  b.c[0] = (c00 * g.c[0] + c01 * g.c[1] + c02 * g.c[2]) * inverse_det;
  b.c[1] = (c01 * g.c[0] + c11 * g.c[1] + c12 * g.c[2]) * inverse_det;
  b.c[2] = (c02 * g.c[0] + c12 * g.c[1] + c22 * g.c[2]) * inverse_det;
  const Mask negative = (b.c[0] < 0.0f) | (b.c[1] < 0.0f) | (b.c[2] < 0.0f);
  if (any(negative)) b = nonnegative_minimiser(h, g, b, negative);
  const Floats largest = max(b.c[0], max(b.c[1], b.c[2]));
  const Floats scale = select(largest > 1.0f, 1.0f / largest, splat(1.0f));
  for (int i = 0; i < 3; ++i) b.c[i] *= scale;
  return b;
}

// error_at() of every lane.
GLTF_PBR_INLINE Floats error_at(Floats m, const Objectives& o) {
  const Vec b = base_at(m, o);
  const Floats prior = m - o.prior_m;
  Floats error = o.prior_weight * prior * prior;
  for (int t = 0; t < o.terms; ++t) {
    const Floats a = o.a0[t] + m * o.a1[t], c = o.c0[t] + m * o.c1[t];
    Vec residual;
    for (int i = 0; i < 3; ++i) residual.c[i] = a * b.c[i] + c - o.target[t].c[i];
    error += quadratic_form(o.metric[t], residual);
  }
  return error;
}

Objectives objectives_for(const SpecGloss* legacy, ErrorModel model) {
  Objectives o;
  Objective one;
  constexpr int kRow[6] = {0, 1, 2, 0, 0, 1}, kColumn[6] = {0, 1, 2, 1, 2, 2};
  const auto put = [&](Symmetric& into, const glm::mat3& from, int l) {
    for (int i = 0; i < 6; ++i) into.e[i][l] = from[kColumn[i]][kRow[i]];
  };
  for (int l = 0; l < kLanes; ++l) {
    one = objective_for(legacy[l], model, l > 0 ? &one : nullptr);
    o.terms = one.terms;
    for (int t = 0; t < one.terms; ++t) {
      const Term& term = one.term[t];
      o.a0[t][l] = term.a0, o.a1[t][l] = term.a1, o.c0[t][l] = term.c0, o.c1[t][l] = term.c1;
      for (int i = 0; i < 3; ++i) o.target[t].c[i][l] = term.target[i];
      put(o.metric[t], one.metric[t], l);
    }
    for (int k = 0; k < 3; ++k) {
      put(o.h[k], one.h[k], l);
      for (int i = 0; i < 3; ++i) o.g[k].c[i][l] = one.g[k][i];
    }
    o.prior_m[l] = one.prior_m;
    o.prior_weight[l] = one.prior_weight;
  }
  return o;
}

// refine() of every lane, each in its own bracket; iterations are the same for all lanes.
GLTF_PBR_INLINE void refine(Floats lo, Floats hi, Floats& m, Floats& error, int iterations, const Objectives& o) {
  constexpr float kInvPhi = 0.6180339887f;
  Floats x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
  Floats e1 = error_at(x1, o), e2 = error_at(x2, o);
  for (int i = 0; i < iterations; ++i) {
    const Mask left = e1 < e2;
    // Left: the minimum is in [lo, x2]; else in [x1, hi]. One new point either way.
    hi = select(left, x2, hi), lo = select(left, lo, x1);
    const Floats kept_x = select(left, x1, x2), kept_e = select(left, e1, e2);
    const Floats fresh_x = select(left, hi - kInvPhi * (hi - lo), lo + kInvPhi * (hi - lo));
    const Floats fresh_e = error_at(fresh_x, o);
    x1 = select(left, fresh_x, kept_x), e1 = select(left, fresh_e, kept_e);
    x2 = select(left, kept_x, fresh_x), e2 = select(left, kept_e, fresh_e);
  }
  if (iterations > 0) {
    const Mask first = e1 < error;
    error = select(first, e1, error), m = select(first, x1, m);
    const Mask second = e2 < error;
    error = select(second, e2, error), m = select(second, x2, m);
  }
}

GLTF_PBR_LANE_CLONES
void solve(const SpecGloss* legacy, MetalRough* out, const SolverSettings& settings) {
  const Objectives o = objectives_for(legacy, settings.error_model);
  const int steps = std::max(1, settings.grid_steps);
  const size_t count = static_cast<size_t>(steps) + 1;
  // Each lane's sampled errors and minima, on the stack (a container of vectors would be code
  // shared between the clones below, compiled for one of them only); the k-th minima of all lanes
  // are refined together.
  float samples[kLanes][kMaxGrid + 1];
  for (int i = 0; i <= steps; ++i) {
    const Floats errors = error_at(splat(static_cast<float>(i) / static_cast<float>(steps)), o);
    for (int l = 0; l < kLanes; ++l) samples[l][i] = errors[l];
  }
  int at[kLanes][kMaxGrid / 2 + 1];
  size_t minima_count[kLanes], most = 0;
  for (int l = 0; l < kLanes; ++l) {
    minima_count[l] = sampled_minima(std::span(samples[l], count), at[l]);
    most = std::max(most, minima_count[l]);
  }
  Minimum minima[kLanes][kMaxGrid / 2 + 1];
  for (size_t j = 0; j < most; ++j) {
    Floats lo = splat(0.0f), hi = splat(1.0f), m = splat(0.5f), error = splat(0.0f);
    for (int l = 0; l < kLanes; ++l) {
      if (j >= minima_count[l]) continue;  // an idle lane refines [0, 1]; its result is dropped
      const Bracket b = bracket_of(at[l][j], count);
      lo[l] = b.lo, hi[l] = b.hi, m[l] = b.m, error[l] = samples[l][at[l][j]];
    }
    refine(lo, hi, m, error, settings.refine_iterations, o);
    for (int l = 0; l < kLanes; ++l)
      if (j < minima_count[l])
        minima[l][j] = {m[l], error[l],
                        prominence(std::span(samples[l], count), std::span(at[l], minima_count[l]), j, error[l])};
  }
  Floats m = splat(0.0f);
  for (int l = 0; l < kLanes; ++l) m[l] = blended_metalness(std::span(minima[l], minima_count[l]));
  const Vec base = base_at(m, o);
  for (int l = 0; l < kLanes; ++l)
    out[l] = {glm::vec3(base.c[0][l], base.c[1][l], base.c[2][l]), m[l], roughness_of(legacy[l])};
}

}  // namespace lane_solver

}  // namespace

Reflectance legacy_reflectance(const SpecGloss& legacy, LegacyReading reading) {
  // Archived KHR_materials_pbrSpecularGlossiness: c_diff = diffuse * (1 - max(specular)).
  // A specular above 1 (gold) must not make the diffuse weight negative.
  const float diffuse_scale = std::max(0.0f, 1.0f - max3(legacy.specular));
  Reflectance r{legacy.diffuse * diffuse_scale, legacy.specular};
  if (reading == LegacyReading::B) r.diffuse *= glm::clamp(1.0f - legacy.specular, 0.0f, 1.0f);
  return r;
}

float appearance_ring_cosine(int ring) {
  return std::sqrt((static_cast<float>(ring) + 0.5f) / static_cast<float>(kAppearanceRings));
}

Appearance legacy_appearance(const SpecGloss& legacy) {
  const glm::vec3 c_a = legacy_reflectance(legacy, LegacyReading::A).diffuse;
  const RingSplitSums split = ring_split_sums(roughness_of(legacy));
  Appearance seen;
  for (int k = 0; k < kAppearanceRings; ++k) {
    const glm::vec2 ab = split.ring[k];
    seen.ring[k] = c_a * (kAppearanceDiffuseLight * dielectric_transmission(ab) / kDielectricDiffuse) +
                   legacy.specular * ab.x + ab.y;
  }
  return seen;
}

Appearance core_appearance(const MetalRough& core) {
  const float m = core.metalness;
  const glm::vec3 f0 = glm::mix(glm::vec3(kDielectricF0), core.base, m);
  const RingSplitSums split = ring_split_sums(core.roughness);
  Appearance seen;
  for (int k = 0; k < kAppearanceRings; ++k) {
    const glm::vec2 ab = split.ring[k];
    seen.ring[k] = core.base * (kAppearanceDiffuseLight * (1.0f - m) * dielectric_transmission(ab)) + f0 * ab.x + ab.y;
  }
  return seen;
}

Appearance specular_extension_appearance(const SpecGloss& legacy) {
  // The extension clamps its F0 to 1 (KHR_materials_specular, "dielectric_f0 = min(..., 1)").
  const glm::vec3 f0 = glm::clamp(legacy.specular, 0.0f, 1.0f);
  const float max_f0 = max3(f0);
  const RingSplitSums split = ring_split_sums(roughness_of(legacy));
  Appearance seen;
  for (int k = 0; k < kAppearanceRings; ++k) {
    const glm::vec2 ab = split.ring[k];
    seen.ring[k] = legacy.diffuse * (kAppearanceDiffuseLight * (1.0f - (max_f0 * ab.x + ab.y))) + f0 * ab.x + ab.y;
  }
  return seen;
}

Reflectance core_reflectance(const MetalRough& core) {
  const float m = core.metalness;
  return {core.base * (1.0f - m) * kDielectricDiffuse, glm::mix(glm::vec3(kDielectricF0), core.base, m)};
}

Reflectance specular_extension_reflectance(glm::vec3 base, glm::vec3 f0) {
  // KHR_materials_specular: the dielectric diffuse is scaled by 1 - max(F0) at normal incidence.
  return {base * std::max(0.0f, 1.0f - max3(f0)), f0};
}

SolverSettings solver_preset(SolverEffort effort, ErrorModel model) {
  switch (effort) {
    case SolverEffort::Fast:
      return {8, 0, false, model};
    case SolverEffort::Exact:
      return {64, 40, false, model};
    case SolverEffort::Reference:
      return {0, 0, true, model};
    case SolverEffort::Balanced:
      break;
  }
  SolverSettings settings;
  settings.error_model = model;
  return settings;
}

MetalRough solve(const SpecGloss& legacy, const SolverSettings& settings) {
  if (settings.reference_formula) return solve_reference(legacy);
  const Objective objective = objective_for(legacy, settings.error_model);

  // Coarse grid over m, then golden-section search around each local minimum of the samples.
  const int steps = std::max(1, settings.grid_steps);
  std::vector<float> samples(static_cast<size_t>(steps) + 1);
  for (int i = 0; i <= steps; ++i)
    samples[static_cast<size_t>(i)] = error_at(static_cast<float>(i) / static_cast<float>(steps), objective);
  const float m = blended_metalness(local_minima(samples, settings.refine_iterations, objective));
  return {base_at(m, objective), m, roughness_of(legacy)};
}

void solve_batch(std::span<const SpecGloss> legacy, std::span<MetalRough> out, const SolverSettings& settings) {
  if (settings.reference_formula) {
    for (size_t i = 0; i < legacy.size(); ++i) out[i] = solve_reference(legacy[i]);
    return;
  }
  if (settings.grid_steps > lane_solver::kMaxGrid) {
    for (size_t i = 0; i < legacy.size(); ++i) out[i] = solve(legacy[i], settings);
    return;
  }
  for (size_t first = 0; first < legacy.size(); first += lanes::kLanes) {
    const size_t n = std::min<size_t>(lanes::kLanes, legacy.size() - first);
    SpecGloss in[lanes::kLanes];
    MetalRough solved[lanes::kLanes];
    for (size_t l = 0; l < lanes::kLanes; ++l) in[l] = legacy[first + std::min(l, n - 1)];  // pad with the last
    lane_solver::solve(in, solved, settings);
    std::copy_n(solved, n, out.begin() + static_cast<std::ptrdiff_t>(first));
  }
}

bool solves_to_its_diffuse(const SpecGloss& legacy) {
  const glm::vec3 d = legacy.diffuse;
  return legacy.specular == glm::vec3(kDielectricF0) && glm::all(glm::greaterThanEqual(d, glm::vec3(0.0f))) &&
         max3(d) <= 1.0f;
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
