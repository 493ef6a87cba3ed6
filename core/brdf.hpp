// BRDF terms of both shading models, scalar and header-only: the preview renders with them, the
// solver's appearance error model integrates them (core/split_sum.hpp), and tests integrate
// exactly what both evaluate.
#pragma once
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <numbers>

namespace gltf_pbr {

constexpr float kPi = std::numbers::pi_v<float>;

// glTF 2.0 Appendix B: the F0 of every core dielectric (ior 1.5).
inline constexpr float kDielectricF0 = 0.04f;
// Where metals begin: the mean F0 below which Unity's material validator calls a metal too dark,
// a little under the darkest metal of Hoffman's table (titanium, 0.496; "Physics and Math of
// Shading", SIGGRAPH 2015).
inline constexpr float kDarkestMetalF0 = 0.45f;

inline float smoothstep01(float t) {
  t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
  return t * t * (3.0f - 2.0f * t);
}

// How metal-like a legacy specular of mean F0 `mean_f0` is, 0 at a core dielectric's 0.04 and 1 at
// the darkest metal, smooth between: the converter solver's metalness prior (converter/solver.hpp)
// and the metalness the material model gives a spec-gloss material.
inline float metal_likeness(float mean_f0) {
  return smoothstep01((mean_f0 - kDielectricF0) / (kDarkestMetalF0 - kDielectricF0));
}

// glTF 2.0 spec, Appendix B.3.5 ("alpha = roughness^2") forbids alpha = 0: a perfect mirror is a
// Dirac lobe that GGX cannot represent. Clamping keeps D finite (Filament's MIN_PERCEPTUAL_ROUGHNESS).
constexpr float kMinAlpha = 0.002f;
inline float alpha_from_roughness(float roughness) {
  const float r = roughness < 0.0f ? 0.0f : (roughness > 1.0f ? 1.0f : roughness);
  return r * r < kMinAlpha ? kMinAlpha : r * r;
}

// glTF 2.0 Appendix B.3.4: Schlick's approximation (Schlick 1994, eq. 15),
// F = F0 + (1 - F0) (1 - |V.H|)^5.
inline glm::vec3 fresnel_schlick(glm::vec3 f0, float v_dot_h) {
  const float c = 1.0f - (v_dot_h < 0.0f ? 0.0f : (v_dot_h > 1.0f ? 1.0f : v_dot_h));
  const float c2 = c * c;
  return f0 + (glm::vec3(1.0f) - f0) * (c2 * c2 * c);
}

// glTF 2.0 Appendix B.3.3: Trowbridge-Reitz / GGX distribution (Walter et al. 2007, eq. 33),
// D = alpha^2 / (pi ((N.H)^2 (alpha^2 - 1) + 1)^2).
inline float distribution_ggx(float n_dot_h, float alpha) {
  const float a2 = alpha * alpha;
  const float d = n_dot_h * n_dot_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

// Height-correlated Smith visibility V = G2 / (4 N.L N.V) for GGX (Heitz 2014, "Understanding
// the Masking-Shadowing Function", eq. 99; Filament's V_SmithGGXCorrelated). Appendix B.3.3 of the
// glTF spec gives the separable form; the design asks for the correlated one.
inline float visibility_smith_ggx_correlated(float n_dot_v, float n_dot_l, float alpha) {
  const float a2 = alpha * alpha;
  const float lambda_v = n_dot_l * std::sqrt(n_dot_v * n_dot_v * (1.0f - a2) + a2);
  const float lambda_l = n_dot_v * std::sqrt(n_dot_l * n_dot_l * (1.0f - a2) + a2);
  const float sum = lambda_v + lambda_l;
  return sum > 0.0f ? 0.5f / sum : 0.0f;
}

// Smith G1 for GGX (Walter et al. 2007, eq. 34), for the weak white furnace test.
inline float smith_g1_ggx(float n_dot_x, float alpha) {
  const float a2 = alpha * alpha;
  return 2.0f * n_dot_x / (n_dot_x + std::sqrt(a2 + (1.0f - a2) * n_dot_x * n_dot_x));
}

// Normalized Blinn-Phong, specular exponent matched to GGX by n = 2 / alpha^2 - 2 (Walter et al.
// 2007, section 5.2), lobe (n + 2) / (8 pi) (N.H)^n (Akenine-Moller et al., "Real-Time Rendering",
// 3rd ed., eq. 7.49): replaces D * V of the microfacet model.
inline float blinn_phong_exponent(float alpha) { return 2.0f / (alpha * alpha) - 2.0f; }
inline float normalized_blinn_phong(float n_dot_h, float alpha) {
  const float n = blinn_phong_exponent(alpha);
  return (n + 2.0f) / (8.0f * kPi) * std::pow(n_dot_h < 0.0f ? 0.0f : n_dot_h, n);
}

enum class SpecularLobe { Ggx, BlinnPhong };

// The inputs a shading point needs, in a common form for both models.
struct SurfaceLobes {
  glm::vec3 diffuse_color{0.0f};  // Lambert weight c_diff
  glm::vec3 f0{kDielectricF0};
  float alpha = 1.0f;
  // The diffuse lobe sits under a layer whose Fresnel it loses: weighted by
  // diffuse_fresnel_scale (1 - F(diffuse_fresnel_f0)) (glTF 2.0 Appendix B).
  glm::vec3 diffuse_fresnel_f0{kDielectricF0};
  float diffuse_fresnel_scale = 1.0f;
};

// Core metal-rough (glTF 2.0 Appendix B.3.5): mix(dielectric_brdf, metal_brdf, m). Schlick is
// linear in F0, so the specular of the mix is one lobe with F0 = lerp(0.04, base, m); the diffuse
// c_diff = lerp(base, 0, m) sits under the dielectric layer and is weighted by (1 - F(0.04)),
// not by the (1 - F) of the mixed F0. alpha = roughness^2.
inline SurfaceLobes metal_rough_lobes(glm::vec3 base, float metalness, float roughness) {
  return {base * (1.0f - metalness), glm::mix(glm::vec3(kDielectricF0), base, metalness),
          alpha_from_roughness(roughness), glm::vec3(kDielectricF0), 1.0f};
}

// Archived KHR_materials_pbrSpecularGlossiness ("Specular - Glossiness" section): c_diff =
// diffuse * (1 - max(specular)), F0 = specular, alpha = (1 - glossiness)^2. Reading A (the
// extension's own text, solver.hpp) takes (1 - max(specular)) for the whole Fresnel loss at
// normal incidence: its diffuse follows the angular shape of the core dielectric layer's
// (1 - F), normalised to 1 at normal incidence, so a 0.04 dielectric shades as its core twin and
// a white one conserves energy. Reading B (the extension's BRDF appendix) also weights the
// diffuse by the (1 - F) of the specular colour.
inline SurfaceLobes spec_gloss_lobes(glm::vec3 diffuse, glm::vec3 specular, float glossiness, bool reading_b) {
  const float max_specular = std::max(specular.x, std::max(specular.y, specular.z));
  return {diffuse * std::max(0.0f, 1.0f - max_specular), specular, alpha_from_roughness(1.0f - glossiness),
          reading_b ? specular : glm::vec3(kDielectricF0), reading_b ? 1.0f : 1.0f / (1.0f - kDielectricF0)};
}

// Radiance reflected towards V from a light of irradiance E (normal incidence) along L:
// f(V, L) * E * N.L, with f = (1 - F) c_diff / pi + F D V (glTF 2.0 Appendix B.3.6).
inline glm::vec3 shade_direct(const SurfaceLobes& s, glm::vec3 n, glm::vec3 v, glm::vec3 l, glm::vec3 irradiance,
                              SpecularLobe lobe) {
  const float n_dot_l = glm::dot(n, l);
  if (n_dot_l <= 0.0f) return glm::vec3(0.0f);
  const float n_dot_v = std::max(glm::dot(n, v), 1e-4f);
  const glm::vec3 h = glm::normalize(v + l);
  const float n_dot_h = std::max(glm::dot(n, h), 0.0f);
  const glm::vec3 f = fresnel_schlick(s.f0, glm::dot(v, h));
  const float specular_lobe = lobe == SpecularLobe::Ggx ? distribution_ggx(n_dot_h, s.alpha) *
                                                              visibility_smith_ggx_correlated(n_dot_v, n_dot_l, s.alpha)
                                                        : normalized_blinn_phong(n_dot_h, s.alpha);
  const glm::vec3 diffuse_weight =
      s.diffuse_fresnel_scale * (glm::vec3(1.0f) - fresnel_schlick(s.diffuse_fresnel_f0, glm::dot(v, h)));
  return (diffuse_weight * s.diffuse_color / kPi + f * specular_lobe) * irradiance * n_dot_l;
}

}  // namespace gltf_pbr
