// Per-texel spec-gloss -> albedo + metalness solver (DESIGN.md, "Conversion").
#pragma once
#include <glm/vec3.hpp>
#include <span>

#include "core/brdf.hpp"          // kDielectricF0
#include "gltf_pbr/gltf_pbr.hpp"  // SolverEffort, ErrorModel

namespace gltf_pbr {

// Legacy KHR_materials_pbrSpecularGlossiness values, linear, factors already applied.
struct SpecGloss {
  glm::vec3 diffuse{1.0f};
  glm::vec3 specular{1.0f};
  float glossiness = 1.0f;
};

// Core glTF 2.0 pbrMetallicRoughness values, linear.
struct MetalRough {
  glm::vec3 base{1.0f};
  float metalness = 1.0f;
  float roughness = 1.0f;
};

// What a material reflects at normal incidence: the diffuse weight and F0. The error model
// compares these, colour by colour, in CIE ΔE2000.
struct Reflectance {
  glm::vec3 diffuse{0.0f};
  glm::vec3 f0{0.0f};
};

// The legacy diffuse is ambiguous (DESIGN.md). Reading A, the archived extension's own text:
// c_diff = diffuse * (1 - max(specular)). Reading B adds the (1 - F0) weighting of the BRDF
// appendix it points to: c_diff = diffuse * (1 - max(specular)) * (1 - specular).
// The solver fits reading A, which makes a 0.04 dielectric convert to base = diffuse exactly;
// reports give both.
enum class LegacyReading { A, B };
Reflectance legacy_reflectance(const SpecGloss& legacy, LegacyReading reading = LegacyReading::A);

// glTF 2.0 Appendix B: F0 = mix(0.04, base, m); the dielectric branch weights the diffuse by
// (1 - F), which is 1 - 0.04 at normal incidence: diffuse = base * (1 - m) * 0.96.
Reflectance core_reflectance(const MetalRough& core);

// KHR_materials_specular's route for a legacy specular (the one glTF-Transform and Blender take):
// base = diffuse, metallic 0, and the specular through specularColorFactor beside an ior so high
// that ((ior - 1) / (ior + 1))^2 is nearly 1 (KHR_materials_ior section "Implementation").
constexpr float kSpecularRouteIor = 1000.0f;
// What that route reflects as written (KHR_materials_specular: F0 = min(F0(ior) specularColor, 1),
// the dielectric diffuse scaled by 1 - max(F0)): F0(1000) = 0.996, so the route is 0.4% short of
// the legacy F0, not exact.
glm::vec3 specular_route_f0(glm::vec3 specular);
Reflectance specular_extension_reflectance(glm::vec3 base, glm::vec3 specular);

struct SolverSettings {
  int grid_steps = 16;             // metalness samples on [0, 1] before refinement
  int refine_iterations = 12;      // golden-section steps: the bracket shrinks to 0.618^12 of 2/16, ~4e-4
  bool reference_formula = false;  // use solve_reference instead (for comparison only)
  ErrorModel error_model = ErrorModel::NormalIncidence;
  bool operator==(const SolverSettings&) const = default;
};
// Named settings for the tool, the library and the benchmark: error against run time.
SolverSettings solver_preset(SolverEffort effort, ErrorModel model = ErrorModel::NormalIncidence);

// The appearance error model: what a viewer sees of each material under the standard
// environment, from kAppearanceRings view angles n·v = mu_k, the rings of equal share of a
// sphere's projected area (mu_k^2 = (k + 1/2) / kAppearanceRings: the projected area with n·v
// below mu is mu^2 of the disc). The environment is reduced to two numbers: the radiance the
// specular lobe mirrors (1) and the light the diffuse lobe receives, E / pi in the same unit
// (kAppearanceDiffuseLight). Diffuse and specular lobes together, by the split sum
// (core/split_sum.hpp; (A, B) at mu_k and roughness), with D = kAppearanceDiffuseLight:
//   core:   L = base (1 - m) w D + F0 A + B,   F0 = mix(0.04, base, m),  w = 1 - (0.04 A + B)
//   legacy: L = c_A w D / 0.96 + specular A + B,   c_A = diffuse (1 - max(specular))  (reading A)
// w is the (1 - F) of glTF Appendix B's dielectric layer averaged over the hemisphere, as the
// preview lights it. Reading A (what viewers take for the legacy diffuse) puts c_A under the same
// layer, normalised to its normal-incidence weight 1 - 0.04, so a 0.04 dielectric converts to
// base = diffuse exactly and a white one conserves energy (as core's does). Both sides share
// the roughness (1 - glossiness), so A and B are the same numbers on both.
inline constexpr int kAppearanceRings = 4;
// The preview's built-in sky and sun (preview/environment.cpp) light a sphere seen from the
// preview's default camera with, on average over its pixels, 1.94 times more diffuse light
// (irradiance / pi, sun included) than the radiance its specular lobe mirrors (prefiltered sky,
// the sun's highlight left out: a few pixels); tests/preview/brdf_test.cpp measures it from the
// environment. Under a uniform environment it would be 1.
inline constexpr float kAppearanceDiffuseLight = 1.94f;
struct Appearance {
  glm::vec3 ring[kAppearanceRings];  // linear radiance seen at mu_0 ... mu_3
};
Appearance legacy_appearance(const SpecGloss& legacy);
Appearance core_appearance(const MetalRough& core);
// The KHR_materials_specular route's look (base = diffuse, F0 = specular, roughness 1 - glossiness):
// the extension's fresnel_mix weights the diffuse by 1 - max(F) over the channels, whose
// hemisphere average is 1 - (max(specular) A + B) (Schlick is monotone in F0 at every angle):
//   L = diffuse (1 - (max(F0) A + B)) D + F0 A + B,   F0 = specular_route_f0(specular), the
// specular clamped to 1 as the extension clamps it. Against the legacy's (reading A) it differs in
// the diffuse, by diffuse D (1 - A - B) (0.04 - max(F0)) / 0.96 (exact for a mirror (A + B = 1),
// for a 0.04 specular and for a black diffuse, off where a rough lobe loses energy), and by the
// route's 0.4% short F0.
Appearance specular_extension_appearance(const SpecGloss& legacy);
float appearance_ring_cosine(int ring);  // mu_k

// Finds base in [0,1]^3 and m in [0,1] from sums of squared CIELAB distances, each term t
// comparing a linear-RGB quantity that the core material gives as a_t(m) base + c_t(m) (a_t, c_t
// affine in m; c_t grey) with the legacy target T_t. m, under both models, and the base under
// normal incidence minimise the normal-incidence terms plus a prior:
//   E = sum_t |J_t (a_t(m) base + c_t(m) - T_t)|^2 + lambda (m - m_prior)^2,
//   - ErrorModel::NormalIncidence: two terms, the diffuse weight (a = 0.96 (1 - m), c = 0,
//     T = c_A) and F0 (a = m, c = 0.04 (1 - m), T = specular).
//   - ErrorModel::Appearance: the metalness of the normal-incidence fit, and the base that, at
//     that m, minimises half the normal-incidence terms and half the appearance terms: two per
//     ring of the appearance model above, each weighing 1 / (2 kAppearanceRings). The radiance
//     seen (a = (1 - m) w D + m A, c = 0.04 (1 - m) A + B, T = the legacy L): the brightness and
//     colour people see, to which both lobes add. And the specular lobe alone (a = m A, the same
//     c, T = specular A + B): an environment has detail (a sun, windows, a horizon) that only the
//     specular lobe mirrors, so a red metal cannot stand in for a red plastic with a grey sheen
//     although their radiance averages agree. Targets above 4 (a specular of 1e30) are scaled
//     down to 4, hue kept.
//     Why not search m on the appearance terms: the appearance terms alone drew spheres under the
//     sky they model closest, but real assets with a sharp sheen farther (Box 5.4 against 3.1
//     ΔE2000 mean); half of each drew real assets closest, but its sum has flat valleys whose two
//     shallow minima trade places, and m stepped by 0.07 in a fine specular sweep. The
//     normal-incidence m is continuous, and for fixed m the base is the unique minimiser of a
//     positive definite quadratic, so the answer is continuous too (bench/RESULTS.md, session 41).
// J_t is CIELAB linearised at T_t (with a gentle CIE94-style chroma compression), so each term is
// a squared ΔE and chroma counts: a grey F0 is not matched by a tinted metal. For fixed m the best
// base is a closed-form 3×3 least squares (the normal-incidence fit's normal equations are
// polynomials in m, built once per input), kept non-negative by an active set and scaled into
// [0,1] with its hue kept, so the search is 1-D over m: a grid, then golden-section refinement of
// each local minimum. m_prior rises smoothly from 0 at the dielectric F0 0.04 to 1 at 0.45, the
// darkest metal F0 (Hoffman's table; Unity's validator). lambda is strong where the diffuse is
// black: a black 0.04 dielectric fits exactly both as m = 0 and as a dark metal (m = 1, base
// 0.04), and the prior picks the dielectric without the jump of the reference formula; it fades
// to weak as the diffuse brightens. Where two minima come close (diffuse and specular of different
// hues), they share the answer by how close and how prominent they are, so m never jumps between
// them. The result is continuous in the inputs, keeps chroma, and is exact for dielectrics at 0.04
// and for metals (black diffuse, mean F0 >= 0.45) under both models. roughness = 1 - g, since
// alpha_legacy = (1 - g)^2 and alpha_core = r^2. Finite for every finite input; inputs above 1
// (gold's F0) are scaled in base, never in the fit.
// Exact idempotence would conflict with continuity on the black-diffuse line (a dark metal fits
// any grey F0 exactly), so a second pass can move the look slightly; tests bound that drift.
MetalRough solve(const SpecGloss& legacy, const SolverSettings& settings = {});

// A legacy material whose specular is exactly the core dielectric's grey F0 and whose diffuse is
// within [0, 1] converts to base = diffuse, metalness 0, with no error under reading A in either
// model: the fit is exact there and the prior points at m = 0, so solve() returns it (tested over the whole diffuse
// cube). Callers may take that answer without the search.
bool solves_to_its_diffuse(const SpecGloss& legacy);

// solve() of many inputs at once, eight side by side in SIMD lanes (AVX2 where the processor has
// it): the same objective, search and blending, with the 3×3 systems solved by cofactors, so each
// answer agrees with solve() to float rounding. An input's answer never depends on the others in
// its batch. out.size() must be legacy.size().
void solve_batch(std::span<const SpecGloss> legacy, std::span<MetalRough> out, const SolverSettings& settings = {});

// The reference formula (archived extension examples, Microsoft glTF-SDK PBRUtils): a scalar
// quadratic on perceived brightness. Kept for comparison in tests and the benchmark.
MetalRough solve_reference(const SpecGloss& legacy);

// The inverse map: a spec-gloss material whose reading-A reflectance equals core_reflectance.
SpecGloss to_spec_gloss(const MetalRough& core);

}  // namespace gltf_pbr
