// Per-texel spec-gloss -> albedo + metalness solver (DESIGN.md, "Conversion").
#pragma once
#include <glm/vec3.hpp>
#include <span>

#include "gltf_pbr/gltf_pbr.hpp"  // SolverEffort

namespace gltf_pbr {

// Legacy KHR_materials_pbrSpecularGlossiness values, linear, factors already applied.
struct SpecGloss {
  glm::vec3 diffuse{1.0f};
  glm::vec3 specular{1.0f};
  float glossiness = 1.0f;
};

// glTF 2.0 Appendix B: the F0 of every core dielectric (ior 1.5).
inline constexpr float kDielectricF0 = 0.04f;

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

// KHR_materials_specular's lossless route (base = diffuse, metallic 0, F0 = specular through
// specularColorFactor with a very high ior): diffuse = base * (1 - max(F0)), F0 = specular.
Reflectance specular_extension_reflectance(glm::vec3 base, glm::vec3 f0);

struct SolverSettings {
  int grid_steps = 16;             // metalness samples on [0, 1] before refinement
  int refine_iterations = 12;      // golden-section steps: the bracket shrinks to 0.618^12 of 2/16, ~4e-4
  bool reference_formula = false;  // use solve_reference instead (for comparison only)
};
// Named settings for the tool, the library and the benchmark: error against run time.
SolverSettings solver_preset(SolverEffort effort);

// Minimises, over base in [0,1]^3 and m in [0,1]:
//   E = |Jd (D_core - D_legacy)|^2 + |Jf (F0_core - F0_legacy)|^2 + lambda (m - m_prior)^2
// with D and F0 from legacy_reflectance (reading A) and core_reflectance. J is CIELAB linearised
// at the legacy colour (with a gentle CIE94-style chroma compression), so each term is a squared
// ΔE and chroma counts: a grey F0 is not matched by a tinted metal. For fixed m the best base is
// a closed-form 3×3 least squares, kept non-negative by an active set and scaled into [0,1] with
// its hue kept, so the search is 1-D over m: a grid, then golden-section refinement of each local
// minimum. m_prior rises smoothly from 0 at the dielectric F0 0.04 to 1 at 0.45, the darkest
// metal F0 (Hoffman's table; Unity's validator). lambda is strong where the diffuse is black: a
// black 0.04 dielectric fits exactly both as m = 0 and as a dark metal (m = 1, base 0.04), and
// the prior picks the dielectric without the jump of the reference formula; it fades to weak as
// the diffuse brightens. Where two minima come close (diffuse and specular of different hues),
// they share the answer by how close and how prominent they are, so m never jumps between them.
// The result is continuous in the inputs, keeps chroma, and is exact for dielectrics at 0.04 and
// for metals (black diffuse, mean F0 >= 0.45). roughness = 1 - g, since alpha_legacy = (1 - g)^2
// and alpha_core = r^2. Finite for every finite input; inputs above 1 (gold's F0) are scaled in
// base, never in the fit.
// Exact idempotence would conflict with continuity on the black-diffuse line (a dark metal fits
// any grey F0 exactly), so a second pass can move the look slightly; tests bound that drift.
MetalRough solve(const SpecGloss& legacy, const SolverSettings& settings = {});

// A legacy material whose specular is exactly the core dielectric's grey F0 and whose diffuse is
// within [0, 1] converts to base = diffuse, metalness 0, with no error under reading A: the fit is
// exact there and the prior points at m = 0, so solve() returns it (tested over the whole diffuse
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
