#include "converter/solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/common.hpp>
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

GLTF_PBR_INLINE float max3(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

GLTF_PBR_INLINE float roughness_of(const SpecGloss& legacy) { return std::clamp(1.0f - legacy.glossiness, 0.0f, 1.0f); }

// (u + eps)^(-2/3) / 3, from a table with linear interpolation on [0, 2] (continuous, and six pow
// calls a texel were a third of the solve time), exact beyond. The lanes look up eight at once
// in the table they fetch once.
constexpr int kSlopeTableSize = 4096;
constexpr float kSlopeTableRange = 2.0f;
using SlopeTable = std::array<float, kSlopeTableSize + 1>;
const SlopeTable& cube_root_slope_table() {
  static const SlopeTable table = [] {
    SlopeTable v;
    for (int i = 0; i <= kSlopeTableSize; ++i)
      v[static_cast<size_t>(i)] =
          std::pow(kSlopeTableRange * static_cast<float>(i) / kSlopeTableSize + kWeightEpsilon, -2.0f / 3.0f) / 3.0f;
    return v;
  }();
  return table;
}
inline float cube_root_slope(float u, const SlopeTable& table) {
  u = std::max(u, 0.0f);
  if (!(u < kSlopeTableRange)) return std::pow(u + kWeightEpsilon, -2.0f / 3.0f) / 3.0f;
  const float x = u * (kSlopeTableSize / kSlopeTableRange);
  const size_t i = static_cast<size_t>(x);
  const float f = x - static_cast<float>(i);
  return table[i] + f * (table[i + 1] - table[i]);
}

// M, row by row: linear sRGB to XYZ (IEC 61966-2-1, D65), each row divided by the white point.
constexpr float kToXyzOverWhite[3][3] = {{0.4124f / 0.95047f, 0.3576f / 0.95047f, 0.1805f / 0.95047f},
                                         {0.2126f, 0.7152f, 0.0722f},
                                         {0.0193f / 1.08883f, 0.1192f / 1.08883f, 0.9505f / 1.08883f}};
// A symmetric 3×3 held as its six entries xx, yy, zz, xy, xz, yz: entry e is (kRow[e], kColumn[e]),
// and (i, j) is entry kIndex[i][j].
constexpr int kRow[6] = {0, 1, 2, 0, 0, 1}, kColumn[6] = {0, 1, 2, 1, 2, 2};
constexpr int kIndex[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};

// Q = JᵀJ for the target t: |J r|^2 = rᵀ Q r, the squared ΔE of a linear-RGB error r near t.
glm::mat3 lab_metric(glm::vec3 t) {
  const SlopeTable& table = cube_root_slope_table();
  float slope[3], f[3];
  for (int c = 0; c < 3; ++c) {
    const float xyz = kToXyzOverWhite[c][0] * t.x + kToXyzOverWhite[c][1] * t.y + kToXyzOverWhite[c][2] * t.z;
    slope[c] = cube_root_slope(xyz, table);
    // (u + eps)^(1/3) = 3 (u + eps) · slope(u): the cube roots come from the slopes already looked up.
    f[c] = 3.0f * (xyz + kWeightEpsilon) * slope[c];
  }
  const float a = 500.0f * (f[0] - f[1]), b = 200.0f * (f[1] - f[2]);
  const float compression = 1.0f / (1.0f + kChromaCompression * std::sqrt(a * a + b * b));
  float j[3][3];  // rows L* = 116 fy, a* = 500 (fx - fy), b* = 200 (fy - fz); columns linear R, G, B
  for (int column = 0; column < 3; ++column) {
    const float x = slope[0] * kToXyzOverWhite[0][column], y = slope[1] * kToXyzOverWhite[1][column],
                z = slope[2] * kToXyzOverWhite[2][column];
    j[0][column] = 116.0f * y;
    j[1][column] = 500.0f * (x - y) * compression;
    j[2][column] = 200.0f * (y - z) * compression;
  }
  glm::mat3 q;
  for (int e = 0; e < 6; ++e) {
    const int r = kRow[e], c = kColumn[e];
    q[c][r] = q[r][c] = j[0][r] * j[0][c] + j[1][r] * j[1][c] + j[2][r] * j[2][c];
  }
  return q;
}

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
// The appearance model's base weighs the normal-incidence terms by this share and its rings by
// the rest (solver.hpp).
constexpr float kNormalIncidenceShare = 0.5f;
// A legacy radiance above this (a specular far above 1, which no material has) enters the fit
// scaled down to it, hue kept: no core material reaches past about 1 anyway, and the squared
// residuals of 1e30 would overflow.
constexpr float kBrightestTarget = 4.0f;
glm::vec3 bounded(glm::vec3 target) {
  const float largest = max3(target);
  return largest > kBrightestTarget ? target * (kBrightestTarget / largest) : target;
}

// The terms of one legacy material (lane_solver::objectives_for and with_appearance_terms build
// the same numbers, in the same operations, eight at a time): the two normal-incidence terms,
// and the appearance model's ring terms at their share.
int normal_incidence_terms(const SpecGloss& legacy, Term* terms) {
  const Reflectance r = legacy_reflectance(legacy, LegacyReading::A);
  terms[0] = {kDielectricDiffuse, -kDielectricDiffuse, 0.0f, 0.0f, 1.0f, r.diffuse};
  terms[1] = {0.0f, 1.0f, kDielectricF0, -kDielectricF0, 1.0f, r.f0};
  return 2;
}
int appearance_terms(const SpecGloss& legacy, Term* terms) {
  const RingSplitSums split = ring_split_sums(roughness_of(legacy));
  const Appearance seen = legacy_appearance(legacy);
  constexpr float kWeight = (1.0f - kNormalIncidenceShare) / kAppearanceRings;
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

// The objective E(m, b) = sum_t |a_t(m) b + c_t(m) (1, 1, 1) - T_t|^2 in the metric Q_t of T_t,
// expanded in b and m: bᵀ H(m) b - 2 g(m)ᵀ b + K(m), with
//   H(m) = sum a² Q,   g(m) = sum a Q (T - c 1),   K(m) = sum (T - c 1)ᵀ Q (T - c 1),
// each a polynomial of degree 2 in m (a and c are affine in m), so evaluating E costs the same
// whatever the number of terms. Where the fit is close, E is a small difference of numbers
// near |T|²_Q (10^3 ΔE² for a mid grey): float would leave noise of 10^-4 on it, enough to turn a
// golden-section step along a flat minimum, so the polynomials are summed and evaluated in
// double from the float terms and metrics; base_for solves H(m) b = g(m) rounded to float.
struct Polynomials {
  double h[3][6];  // symmetric: xx, yy, zz, xy, xz, yz
  double g[3][3];
  double k[3];
};
// Adds one term to the polynomials, in double (lane_solver::accumulate is its mirror).
void accumulate(Polynomials& p, const Term& term, const glm::mat3& q) {
  double qd[3][3], t[3], pull[3], grey[3];
  for (int i = 0; i < 3; ++i) {
    t[i] = term.target[i];
    for (int j = 0; j < 3; ++j) qd[i][j] = q[j][i];
  }
  double tqt = 0.0, one_qt = 0.0, one_q_one = 0.0;
  for (int i = 0; i < 3; ++i) {
    pull[i] = qd[i][0] * t[0] + qd[i][1] * t[1] + qd[i][2] * t[2];
    grey[i] = qd[i][0] + qd[i][1] + qd[i][2];
    tqt += t[i] * pull[i], one_qt += pull[i], one_q_one += grey[i];
  }
  const double a0 = term.a0, a1 = term.a1, c0 = term.c0, c1 = term.c1;
  for (int e = 0; e < 6; ++e) {
    const double qe = qd[kRow[e]][kColumn[e]];
    p.h[0][e] += a0 * a0 * qe, p.h[1][e] += 2.0 * a0 * a1 * qe, p.h[2][e] += a1 * a1 * qe;
  }
  for (int i = 0; i < 3; ++i) {
    const double rest = pull[i] - c0 * grey[i];  // Q (T - c0 1)
    p.g[0][i] += a0 * rest, p.g[1][i] += a1 * rest - a0 * c1 * grey[i], p.g[2][i] -= a1 * c1 * grey[i];
  }
  p.k[0] += tqt - 2.0 * c0 * one_qt + c0 * c0 * one_q_one;
  p.k[1] += 2.0 * c1 * (c0 * one_q_one - one_qt);
  p.k[2] += c1 * c1 * one_q_one;
}

// What the metalness search minimises, fixed for all m: the polynomials and the prior.
struct Objective {
  Polynomials exact;
  float prior_m, prior_weight;
};

// The prior on metalness of one legacy material (solver.hpp): where it points, how strongly.
GLTF_PBR_INLINE std::pair<float, float> metalness_prior(const SpecGloss& legacy) {
  const float mean_f0 = (legacy.specular.x + legacy.specular.y + legacy.specular.z) / 3.0f;
  const Reflectance r = legacy_reflectance(legacy, LegacyReading::A);
  return {metal_likeness(mean_f0), kPriorWeightOnBright + (kPriorWeightOnBlack - kPriorWeightOnBright) *
                                                              (1.0f - smoothstep01(max3(r.diffuse) / kBrightDiffuse))};
}

// The metalness fit of one legacy material: the normal-incidence terms and the prior.
Objective objective_for(const SpecGloss& legacy) {
  Term terms[2];
  const int count = normal_incidence_terms(legacy, terms);
  Objective o{};
  for (int t = 0; t < count; ++t) accumulate(o.exact, terms[t], terms[t].weight * lab_metric(terms[t].target));
  std::tie(o.prior_m, o.prior_weight) = metalness_prior(legacy);
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

// H(m) and g(m) (Polynomials), evaluated in double.
struct AtMetalness {
  double m, h[6], g[3];
};
AtMetalness at_metalness(float m, const Objective& o) {
  const Polynomials& p = o.exact;
  AtMetalness at{m, {}, {}};
  const double m2 = at.m * at.m;
  for (int e = 0; e < 6; ++e) at.h[e] = p.h[0][e] + at.m * p.h[1][e] + m2 * p.h[2][e];
  for (int i = 0; i < 3; ++i) at.g[i] = p.g[0][i] + at.m * p.g[1][i] + m2 * p.g[2][i];
  return at;
}

// The base for metalness m: the best non-negative base for the terms at m, whose normal
// equations are H(m) b = g(m) (in float), then brought into [0, 1] by scaling the whole colour
// when a channel exceeds 1 (a saturated diffuse of 1.0 needs 1/0.96; gold's red F0 is 1.022).
// Clipping that channel alone would shift the hue; the scale is 1 at the gamut edge, so the
// result stays continuous. Each metric is positive definite (J is a product of invertible
// matrices) and the terms' scales a(m) never all vanish on [0, 1], so H is invertible: no
// epsilon is needed.
glm::vec3 base_for(const AtMetalness& at) {
  glm::mat3 h;
  for (int e = 0; e < 6; ++e) h[kColumn[e]][kRow[e]] = h[kRow[e]][kColumn[e]] = static_cast<float>(at.h[e]);
  const glm::vec3 base = nonnegative_minimiser(h, glm::vec3(at.g[0], at.g[1], at.g[2]));
  const float largest = max3(base);
  return largest > 1.0f ? base / largest : base;
}

// The appearance model's H and g at the metalness the fit chose (solver.hpp): the fit's own at
// their share, plus the ring terms evaluated at that m (each term's part of the polynomials of
// accumulate(), at one m).
AtMetalness with_appearance_terms(AtMetalness at, const SpecGloss& legacy) {
  for (double& e : at.h) e *= kNormalIncidenceShare;
  for (double& e : at.g) e *= kNormalIncidenceShare;
  Term terms[kMaxTerms];
  const int count = appearance_terms(legacy, terms);
  for (int t = 0; t < count; ++t) {
    const Term& term = terms[t];
    const glm::mat3 q = term.weight * lab_metric(term.target);
    const double a = term.a0 + at.m * term.a1, c = term.c0 + at.m * term.c1;
    for (int e = 0; e < 6; ++e) at.h[e] += a * a * q[kColumn[e]][kRow[e]];
    for (int i = 0; i < 3; ++i) {
      double pull = 0.0, grey = 0.0;  // (Q T)_i, (Q 1)_i
      for (int j = 0; j < 3; ++j) pull += q[j][i] * static_cast<double>(term.target[j]), grey += q[j][i];
      at.g[i] += a * (pull - c * grey);
    }
  }
  return at;
}

// The objective at m, for the base that m is given (Polynomials).
float error_at(float m, const Objective& o) {
  const AtMetalness at = at_metalness(m, o);
  const glm::vec3 base = base_for(at);
  const double b[3] = {base.x, base.y, base.z}, *h = at.h, *g = at.g, *k = o.exact.k;
  const double quadratic = h[0] * b[0] * b[0] + h[1] * b[1] * b[1] + h[2] * b[2] * b[2] +
                           2.0 * (h[3] * b[0] * b[1] + h[4] * b[0] * b[2] + h[5] * b[1] * b[2]);
  const double prior = at.m - static_cast<double>(o.prior_m);
  return static_cast<float>(quadratic - 2.0 * (g[0] * b[0] + g[1] * b[1] + g[2] * b[2]) + k[0] + at.m * k[1] +
                            at.m * at.m * k[2] + static_cast<double>(o.prior_weight) * prior * prior);
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
GLTF_PBR_INLINE size_t sampled_minima(std::span<const float> samples, std::span<int> at) {
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
GLTF_PBR_INLINE Bracket bracket_of(int i, size_t samples) {
  const float step = 1.0f / static_cast<float>(std::max<size_t>(1, samples - 1));
  const float m = static_cast<float>(i) * step;
  return {std::max(0.0f, m - step), std::min(1.0f, m + step), m};
}

// How far minimum j (refined to `error`) lies below the highest sample between it and the
// nearest other minimum: infinite with none.
GLTF_PBR_INLINE float prominence(std::span<const float> samples, std::span<const int> at, size_t j, float error) {
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
GLTF_PBR_INLINE float blended_metalness(std::span<const Minimum> minima) {
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
// objective (built in the same operations, eight at a time), grid, refinement and blending as
// solve(); the 3×3 systems are solved by cofactors
// rather than glm::inverse, so results agree with solve() to float rounding, not bit for bit.
// The rare lane whose unconstrained base has a negative channel takes the scalar active set.
// Every helper that solve() calls, here and above (bracket_of, prominence, ...), is
// GLTF_PBR_INLINE: a call out of its AVX2 clone into plain x86-64 code spilled the lanes, 330 of
// 790 ns a solve (bench/RESULTS.md, session 29).
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

// A symmetric 3×3 matrix per lane in double, and a vector: Polynomials in lanes.
struct SymmetricD {
  Doubles e[6];
};
struct VecD {
  Doubles c[3];
};

// What solve() builds per input, as structure of arrays (Objective).
struct Objectives {
  SymmetricD exact_h[3];
  VecD exact_g[3];
  Doubles exact_k[3];
  Floats prior_m, prior_weight;
};

// nonnegative_minimiser() of the lanes in `todo`, whose unconstrained minimiser `b` has a negative
// channel. For a positive definite H the constrained minimiser is the one point that meets the
// KKT conditions: the free channels solve their reduced system and are >= 0, and the gradient
// H b - g of each channel held at 0 is >= 0. The lanes try the free sets in turn (two channels,
// one, none) and keep the first that meets them; a lane that rounding leaves without one takes
// the scalar active set.
GLTF_PBR_INLINE Vec nonnegative_minimiser(const Symmetric& h, const Vec& g, Vec b, Mask todo) {
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

// at_metalness() of every lane.
struct AtMetalness {
  Doubles m, h[6], g[3];
};
GLTF_PBR_INLINE AtMetalness at_metalness(Floats m, const Objectives& o) {
  AtMetalness at;
  at.m = to_doubles(m);
  const Doubles m2 = at.m * at.m;
  for (int e = 0; e < 6; ++e) at.h[e] = o.exact_h[0].e[e] + at.m * o.exact_h[1].e[e] + m2 * o.exact_h[2].e[e];
  for (int i = 0; i < 3; ++i) at.g[i] = o.exact_g[0].c[i] + at.m * o.exact_g[1].c[i] + m2 * o.exact_g[2].c[i];
  return at;
}

// base_for() of every lane.
GLTF_PBR_INLINE Vec base_for(const AtMetalness& at) {
  Symmetric h;
  for (int e = 0; e < 6; ++e) h.e[e] = to_floats(at.h[e]);
  Vec g;
  for (int i = 0; i < 3; ++i) g.c[i] = to_floats(at.g[i]);
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
  const AtMetalness at = at_metalness(m, o);
  const Vec base = base_for(at);
  Doubles b[3];
  for (int i = 0; i < 3; ++i) b[i] = to_doubles(base.c[i]);
  const Doubles *h = at.h, *g = at.g;
  const Doubles quadratic = h[0] * b[0] * b[0] + h[1] * b[1] * b[1] + h[2] * b[2] * b[2] +
                            2.0 * (h[3] * b[0] * b[1] + h[4] * b[0] * b[2] + h[5] * b[1] * b[2]);
  const Doubles prior = at.m - to_doubles(o.prior_m);
  return to_floats(quadratic - 2.0 * (g[0] * b[0] + g[1] * b[1] + g[2] * b[2]) + o.exact_k[0] + at.m * o.exact_k[1] +
                   at.m * at.m * o.exact_k[2] + to_doubles(o.prior_weight) * prior * prior);
}

// lab_metric() of every lane, times `weight`: the same formula, with J written out row by row
// (L* = 116 fy, a* = 500 (fx - fy), b* = 200 (fy - fz) of the slope-scaled rows of M).
GLTF_PBR_INLINE Symmetric lab_metric(const Vec& t, float weight, const SlopeTable& table) {
  Floats xyz[3], slope[3], f[3];
  for (int c = 0; c < 3; ++c) {
    xyz[c] = kToXyzOverWhite[c][0] * t.c[0] + kToXyzOverWhite[c][1] * t.c[1] + kToXyzOverWhite[c][2] * t.c[2];
    for (int l = 0; l < kLanes; ++l) slope[c][l] = cube_root_slope(xyz[c][l], table);
    f[c] = 3.0f * (xyz[c] + kWeightEpsilon) * slope[c];
  }
  const Floats a = 500.0f * (f[0] - f[1]), b = 200.0f * (f[1] - f[2]);
  Floats compression;
  for (int l = 0; l < kLanes; ++l)
    compression[l] = 1.0f / (1.0f + kChromaCompression * std::sqrt(a[l] * a[l] + b[l] * b[l]));
  Floats j[3][3];  // rows L*, a*, b*; columns linear R, G, B
  for (int column = 0; column < 3; ++column) {
    const Floats x = slope[0] * kToXyzOverWhite[0][column], y = slope[1] * kToXyzOverWhite[1][column],
                 z = slope[2] * kToXyzOverWhite[2][column];
    j[0][column] = 116.0f * y;
    j[1][column] = 500.0f * (x - y) * compression;
    j[2][column] = 200.0f * (y - z) * compression;
  }
  Symmetric q;
  for (int e = 0; e < 6; ++e) {
    const int r = kRow[e], c = kColumn[e];
    q.e[e] = weight * (j[0][r] * j[0][c] + j[1][r] * j[1][c] + j[2][r] * j[2][c]);
  }
  return q;
}

// accumulate() of every lane, for a term a(m) = a0 + m a1, c(m) = c0 + m c1 against `target`.
GLTF_PBR_INLINE void accumulate(Objectives& o, Floats a0f, Floats a1f, Floats c0f, Floats c1f, const Vec& target,
                                const Symmetric& metric) {
  Doubles q[6], t[3], pull[3], grey[3];
  for (int e = 0; e < 6; ++e) q[e] = to_doubles(metric.e[e]);
  for (int i = 0; i < 3; ++i) t[i] = to_doubles(target.c[i]);
  Doubles tqt{}, one_qt{}, one_q_one{};
  for (int i = 0; i < 3; ++i) {
    pull[i] = q[kIndex[i][0]] * t[0] + q[kIndex[i][1]] * t[1] + q[kIndex[i][2]] * t[2];
    grey[i] = q[kIndex[i][0]] + q[kIndex[i][1]] + q[kIndex[i][2]];
    tqt += t[i] * pull[i], one_qt += pull[i], one_q_one += grey[i];
  }
  const Doubles a0 = to_doubles(a0f), a1 = to_doubles(a1f), c0 = to_doubles(c0f), c1 = to_doubles(c1f);
  for (int e = 0; e < 6; ++e) {
    o.exact_h[0].e[e] += a0 * a0 * q[e];
    o.exact_h[1].e[e] += 2.0 * a0 * a1 * q[e];
    o.exact_h[2].e[e] += a1 * a1 * q[e];
  }
  for (int i = 0; i < 3; ++i) {
    const Doubles rest = pull[i] - c0 * grey[i];  // Q (T - c0 1)
    o.exact_g[0].c[i] += a0 * rest;
    o.exact_g[1].c[i] += a1 * rest - a0 * c1 * grey[i];
    o.exact_g[2].c[i] -= a1 * c1 * grey[i];
  }
  o.exact_k[0] += tqt - 2.0 * c0 * one_qt + c0 * c0 * one_q_one;
  o.exact_k[1] += 2.0 * c1 * (c0 * one_q_one - one_qt);
  o.exact_k[2] += c1 * c1 * one_q_one;
}

// bounded() of every lane.
GLTF_PBR_INLINE Vec bounded(Vec target) {
  const Floats largest = max(target.c[0], max(target.c[1], target.c[2]));
  const Floats scale = select(largest > kBrightestTarget, kBrightestTarget / largest, splat(1.0f));
  for (int c = 0; c < 3; ++c) target.c[c] *= scale;
  return target;
}

// The legacy reflectance of eight inputs: F0, and the diffuse weight under reading A.
struct LegacyLanes {
  Vec specular, c_a;
};
GLTF_PBR_INLINE LegacyLanes legacy_lanes(const SpecGloss* legacy) {
  LegacyLanes r;
  for (int l = 0; l < kLanes; ++l) {
    const glm::vec3 diffuse = legacy_reflectance(legacy[l], LegacyReading::A).diffuse;
    for (int c = 0; c < 3; ++c) r.specular.c[c][l] = legacy[l].specular[c], r.c_a.c[c][l] = diffuse[c];
  }
  return r;
}

// objective_for() of eight inputs at once: the terms of normal_incidence_terms(), their metrics
// and the polynomials, in lanes (inlined into solve(), so its AVX2 clone builds them too).
GLTF_PBR_INLINE Objectives objectives_for(const SpecGloss* legacy, const LegacyLanes& reflectance) {
  const SlopeTable& table = cube_root_slope_table();
  Objectives o{};
  for (int l = 0; l < kLanes; ++l) {
    const auto [prior_m, prior_weight] = metalness_prior(legacy[l]);
    o.prior_m[l] = prior_m, o.prior_weight[l] = prior_weight;
  }
  const auto& [specular, c_a] = reflectance;
  accumulate(o, splat(kDielectricDiffuse), splat(-kDielectricDiffuse), splat(0.0f), splat(0.0f), c_a,
             lab_metric(c_a, 1.0f, table));
  accumulate(o, splat(0.0f), splat(1.0f), splat(kDielectricF0), splat(-kDielectricF0), specular,
             lab_metric(specular, 1.0f, table));
  return o;
}

// One term's part of H and g at the metalness of `at` (accumulate()'s polynomials, at one m).
GLTF_PBR_INLINE void accumulate_at(AtMetalness& at, Floats a0, Floats a1, Floats c0, Floats c1, const Vec& target,
                                   const Symmetric& metric) {
  const Doubles a = to_doubles(a0) + at.m * to_doubles(a1), c = to_doubles(c0) + at.m * to_doubles(c1);
  Doubles q[6], t[3];
  for (int e = 0; e < 6; ++e) q[e] = to_doubles(metric.e[e]);
  for (int i = 0; i < 3; ++i) t[i] = to_doubles(target.c[i]);
  for (int e = 0; e < 6; ++e) at.h[e] += a * a * q[e];
  for (int i = 0; i < 3; ++i) {
    const Doubles pull = q[kIndex[i][0]] * t[0] + q[kIndex[i][1]] * t[1] + q[kIndex[i][2]] * t[2];
    const Doubles grey = q[kIndex[i][0]] + q[kIndex[i][1]] + q[kIndex[i][2]];
    at.g[i] += a * (pull - c * grey);
  }
}

// with_appearance_terms() of eight inputs at once: the terms of appearance_terms(), at m.
GLTF_PBR_INLINE AtMetalness with_appearance_terms(AtMetalness at, const SpecGloss* legacy,
                                                  const LegacyLanes& reflectance) {
  const SlopeTable& table = cube_root_slope_table();
  for (Doubles& e : at.h) e *= static_cast<double>(kNormalIncidenceShare);
  for (Doubles& e : at.g) e *= static_cast<double>(kNormalIncidenceShare);
  const auto& [specular, c_a] = reflectance;
  RingSplitSums split[kLanes];
  for (int l = 0; l < kLanes; ++l) split[l] = ring_split_sums(roughness_of(legacy[l]));
  constexpr float kWeight = (1.0f - kNormalIncidenceShare) / kAppearanceRings;
  for (int k = 0; k < kAppearanceRings; ++k) {
    Floats a, b;  // the ring's split sum (A, B)
    for (int l = 0; l < kLanes; ++l) a[l] = split[l].ring[k].x, b[l] = split[l].ring[k].y;
    const Floats w = 1.0f - (kDielectricF0 * a + b);  // dielectric_transmission
    const Floats lit = kAppearanceDiffuseLight * w;
    const Floats c0 = kDielectricF0 * a + b, c1 = -kDielectricF0 * a;
    Vec seen, mirrored;  // legacy_appearance's ring (in its order of operations), and the specular lobe alone
    for (int c = 0; c < 3; ++c) {
      seen.c[c] = c_a.c[c] * (kAppearanceDiffuseLight * w / kDielectricDiffuse) + specular.c[c] * a + b;
      mirrored.c[c] = specular.c[c] * a + b;
    }
    const Vec seen_target = bounded(seen), mirrored_target = bounded(mirrored);
    accumulate_at(at, lit, a - lit, c0, c1, seen_target, lab_metric(seen_target, kWeight, table));
    accumulate_at(at, splat(0.0f), a, c0, c1, mirrored_target, lab_metric(mirrored_target, kWeight, table));
  }
  return at;
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
  const LegacyLanes reflectance = legacy_lanes(legacy);  // read by both steps
  const Objectives o = objectives_for(legacy, reflectance);
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
  const AtMetalness fit = at_metalness(m, o);
  const Vec base =
      base_for(settings.error_model == ErrorModel::Appearance ? with_appearance_terms(fit, legacy, reflectance) : fit);
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
  const glm::vec3 f0 = specular_route_f0(legacy.specular);
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

glm::vec3 specular_route_f0(glm::vec3 specular) {
  // In the operations of the viewer's reading (core/material_model.cpp): KHR_materials_ior's
  // F0 = ((ior - 1) / (ior + 1))^2, then KHR_materials_specular's "dielectric_f0 = min(..., 1)".
  const float r = (kSpecularRouteIor - 1.0f) / (kSpecularRouteIor + 1.0f);
  return glm::clamp(glm::vec3(r * r) * specular, 0.0f, 1.0f);
}

Reflectance specular_extension_reflectance(glm::vec3 base, glm::vec3 specular) {
  // KHR_materials_specular: the dielectric diffuse is scaled by 1 - max(F0) at normal incidence.
  const glm::vec3 f0 = specular_route_f0(specular);
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
  const Objective objective = objective_for(legacy);

  // Coarse grid over m, then golden-section search around each local minimum of the samples.
  const int steps = std::max(1, settings.grid_steps);
  std::vector<float> samples(static_cast<size_t>(steps) + 1);
  for (int i = 0; i <= steps; ++i)
    samples[static_cast<size_t>(i)] = error_at(static_cast<float>(i) / static_cast<float>(steps), objective);
  const float m = blended_metalness(local_minima(samples, settings.refine_iterations, objective));
  const AtMetalness fit = at_metalness(m, objective);
  const glm::vec3 base =
      base_for(settings.error_model == ErrorModel::Appearance ? with_appearance_terms(fit, legacy) : fit);
  return {base, m, roughness_of(legacy)};
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
