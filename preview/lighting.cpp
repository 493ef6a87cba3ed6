// Sun + split-sum image-based lighting of a G-buffer (see lighting.hpp).
#include "preview/lighting.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "core/color.hpp"
#include "preview/lighting_lanes.hpp"

namespace gltf_pbr::preview {

namespace {

// The tone maps, inlined into the lighting loop (the exported functions below wrap them).
[[gnu::always_inline]] inline glm::vec3 pbr_neutral(glm::vec3 color) {
  constexpr float kStartCompression = 0.8f - 0.04f, kDesaturation = 0.15f;
  const float x = std::min(color.x, std::min(color.y, color.z));
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  color -= offset;
  const float peak = std::max(color.x, std::max(color.y, color.z));
  if (peak < kStartCompression) return color;
  constexpr float d = 1.0f - kStartCompression;
  const float new_peak = 1.0f - d * d / (peak + d - kStartCompression);
  color *= new_peak / peak;
  const float g = 1.0f - 1.0f / (kDesaturation * (peak - new_peak) + 1.0f);
  return glm::mix(color, glm::vec3(new_peak), g);
}

[[gnu::always_inline]] inline glm::vec3 aces(glm::vec3 x) {
  return glm::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

[[gnu::always_inline]] inline void tone_map_pixel(glm::vec3 radiance, const LightingOptions& options,
                                                  std::uint8_t* rgb) {
  glm::vec3 c = glm::max(radiance * options.exposure, glm::vec3(0.0f));
  c = options.tone_map == ToneMap::KhronosPbrNeutral ? pbr_neutral(c)
      : options.tone_map == ToneMap::Aces            ? aces(c)
                                                     : glm::clamp(c, 0.0f, 1.0f);
  for (int k = 0; k < 3; ++k) rgb[k] = encode_srgb8(c[k]);
}

// What both sides share at a pixel: the (bent) normal, the view vector, the reflected direction's
// map coordinates and the diffuse irradiance. Computed once, used by "before" and "after".
struct PixelGeometry {
  glm::vec3 n, v;
  float n_dot_v;
  glm::vec2 reflected_uv;
  glm::vec3 irradiance;
};

PixelGeometry prepare(glm::vec3 n, glm::vec3 v, const Environment& env) {
  // A normal from a normal map can face away from the viewer; bend it back to just inside the
  // visible hemisphere so that N.V > 0 and no term divides by zero (the visible-normal clamp
  // that real-time renderers apply, e.g. Filament's clampNoV).
  float n_dot_v = glm::dot(n, v);
  if (n_dot_v < 1e-3f) {
    n = glm::normalize(n + v * (1e-3f - n_dot_v));
    n_dot_v = std::max(glm::dot(n, v), 1e-4f);
  }
  const glm::vec3 reflected = 2.0f * n_dot_v * n - v;
  return {n, v, n_dot_v, equirect_uv(reflected), env.irradiance(n)};
}

glm::vec3 shade_prepared(const SurfaceLobes& lobes, float roughness, const PixelGeometry& g, float occlusion,
                         glm::vec3 emissive, const Environment& env, const LightingOptions& options) {
  glm::vec3 color(0.0f);
  if (options.sun && env.sun_irradiance != glm::vec3(0.0f))
    color += shade_direct(lobes, g.n, g.v, env.sun_direction, env.sun_irradiance, options.lobe);
  // Split sum (Karis 2013): specular = prefiltered(R, roughness) * (F0 A + B).
  const glm::vec2 dfg = dfg_lookup(g.n_dot_v, roughness);
  const glm::vec3 specular = env.prefiltered_radiance_uv(g.reflected_uv, roughness) * (lobes.f0 * dfg.x + dfg.y);
  // Diffuse: Lambert on SH irradiance, E / pi; the (1 - F) weighting of glTF Appendix B is
  // averaged over the hemisphere by the split-sum term of the layer it sits under, 1 - (F0_d A + B)
  // (F0_d = 0.04 for metal-rough and legacy reading A, the specular colour for reading B), which
  // makes a white non-absorbing dielectric reflect a uniform environment exactly (white furnace).
  const glm::vec3 diffuse = lobes.diffuse_color * g.irradiance / kPi * lobes.diffuse_fresnel_scale *
                            (glm::vec3(1.0f) - (lobes.diffuse_fresnel_f0 * dfg.x + dfg.y));
  // glTF 2.0 section 3.9.4: occlusion darkens indirect light only.
  color += (diffuse + specular) * occlusion + emissive;
  return std::isfinite(color.x + color.y + color.z) ? color : glm::vec3(0.0f);
}

glm::vec3 shade_texel(const GBufferTexel& t, Side side, const PixelGeometry& g, const Environment& env,
                      const LightingOptions& options) {
  if (side == Side::After)
    return shade_prepared(metal_rough_lobes(t.color_a, t.color_b.x, t.scalar), t.scalar, g, t.occlusion, t.emissive,
                          env, options);
  return shade_prepared(spec_gloss_lobes(t.color_a, t.color_b, t.scalar, options.legacy_reading_b), 1.0f - t.scalar, g,
                        t.occlusion, t.emissive, env, options);
}

HdrImage empty_image(const GBuffer& g) {
  HdrImage image{g.width, g.height, {}, {}};
  image.radiance.resize(g.depth.size());
  image.covered.resize(g.depth.size());
  return image;
}

LitPair empty_pair(const GBuffers& gbuffers, bool keep_radiance) {
  const size_t count = gbuffers.after.depth.size();
  LitPair out{std::vector<std::uint8_t>(count * 3),
              std::vector<std::uint8_t>(count * 3),
              std::vector<std::uint8_t>(count),
              {},
              {}};
  if (keep_radiance) {
    out.before_hdr = empty_image(gbuffers.before);
    out.after_hdr = empty_image(gbuffers.after);
  }
  return out;
}

}  // namespace

glm::vec3 shade_point(const SurfaceLobes& lobes, float roughness, glm::vec3 n, glm::vec3 v, float occlusion,
                      glm::vec3 emissive, const Environment& env, const LightingOptions& options) {
  return shade_prepared(lobes, roughness, prepare(n, v, env), occlusion, emissive, env, options);
}

LitPair light_both(const GBuffers& gbuffers, const Environment& env, const Camera& camera,
                   const LightingOptions& options, bool keep_radiance) {
  LitPair out = empty_pair(gbuffers, keep_radiance);
  const RayGenerator rays(camera, gbuffers.after.width, gbuffers.after.height);
  const LightingPass pass{gbuffers, env, rays, options, out, keep_radiance};
  parallel_dynamic(gbuffers.after.height, [&](std::int64_t y) { light_row(pass, y); });
  return out;
}

LitPair light_both_reference(const GBuffers& gbuffers, const Environment& env, const Camera& camera,
                             const LightingOptions& options, bool keep_radiance) {
  const GBuffer& a = gbuffers.after;
  LitPair out = empty_pair(gbuffers, keep_radiance);
  const RayGenerator rays(camera, a.width, a.height);
  parallel_dynamic(a.height, [&](std::int64_t y) {
    for (int x = 0; x < a.width; ++x) {
      const size_t i = static_cast<size_t>(y) * static_cast<size_t>(a.width) + static_cast<size_t>(x);
      const glm::vec3 ray =
          glm::normalize(rays.unnormalised(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f));
      const GBufferTexel after = read_after(a, i);
      glm::vec3 before_radiance, after_radiance;
      if (after.covered) {
        const GBufferTexel before = read_before_material(gbuffers.before, i);  // normal: after's
        // Both sides share the normal buffer's geometry: one set of environment look-ups.
        const PixelGeometry geometry = prepare(after.normal, -ray, env);
        after_radiance = shade_texel(after, Side::After, geometry, env, options);
        before_radiance = shade_texel(before, Side::Before, geometry, env, options);
        tone_map_pixel(before_radiance, options, &out.before[i * 3]);
        tone_map_pixel(after_radiance, options, &out.after[i * 3]);
      } else {  // the same sky behind both sides: mapped once
        before_radiance = after_radiance = env.background(ray);
        tone_map_pixel(after_radiance, options, &out.after[i * 3]);
        std::copy_n(&out.after[i * 3], 3, &out.before[i * 3]);
      }
      out.covered[i] = after.covered ? 1 : 0;
      if (keep_radiance) {
        out.before_hdr.radiance[i] = before_radiance;
        out.after_hdr.radiance[i] = after_radiance;
        out.before_hdr.covered[i] = out.after_hdr.covered[i] = out.covered[i];
      }
    }
  });
  return out;
}

glm::vec3 khronos_pbr_neutral(glm::vec3 color) { return pbr_neutral(color); }

glm::vec3 aces_fitted(glm::vec3 x) { return aces(x); }

void tone_map_srgb8(glm::vec3 radiance, const LightingOptions& options, std::uint8_t* rgb) {
  tone_map_pixel(radiance, options, rgb);
}

std::vector<std::uint8_t> to_srgb8(const HdrImage& image, const LightingOptions& options) {
  std::vector<std::uint8_t> out(image.radiance.size() * 3);
  parallel_dynamic(image.height, [&](std::int64_t y) {
    for (int x = 0; x < image.width; ++x) {
      const size_t i = static_cast<size_t>(y) * static_cast<size_t>(image.width) + static_cast<size_t>(x);
      tone_map_pixel(image.radiance[i], options, &out[i * 3]);
    }
  });
  return out;
}

}  // namespace gltf_pbr::preview
