// The lighting pass: reads one side's G-buffer and lights it with a sun plus the image-based
// light, then tone-maps to sRGB. Both sides run the same code except for their BRDF inputs.
#pragma once
#include <cstdint>
#include <vector>

#include "core/brdf.hpp"
#include "preview/environment.hpp"
#include "preview/gbuffer.hpp"

namespace gltf_pbr::preview {

enum class ToneMap { KhronosPbrNeutral, Aces, Clamp };

struct LightingOptions {
  SpecularLobe lobe = SpecularLobe::Ggx;
  bool legacy_reading_b = false;  // "before" diffuse also weighted by (1 - F) (solver.hpp, LegacyReading)
  bool sun = true;
  float exposure = 1.0f;
  ToneMap tone_map = ToneMap::KhronosPbrNeutral;
};

struct HdrImage {
  int width = 0, height = 0;
  TexelBuffer<glm::vec3> radiance;    // sized, not cleared: the lighting pass writes every pixel
  TexelBuffer<std::uint8_t> covered;  // 1 where geometry was drawn
};

enum class Side { Before, After };

// Both sides in one pass (they share normals and so environment look-ups), tone-mapped to 8-bit
// sRGB in the same pass. The normals are the same buffer content on both sides by construction
// (fill_gbuffers, sphere_grid_gbuffers). The HDR radiance, 24 bytes a pixel for the pair, is
// kept only when asked for.
struct LitPair {
  std::vector<std::uint8_t> before, after;  // 8-bit sRGB RGB, as to_srgb8
  std::vector<std::uint8_t> covered;        // 1 where geometry was drawn
  HdrImage before_hdr, after_hdr;           // empty unless keep_radiance
};
LitPair light_both(const GBuffers& gbuffers, const Environment& env, const Camera& camera,
                   const LightingOptions& options, bool keep_radiance = false);
// The same pass a pixel at a time: the reference that light_both's eight-pixel lanes
// (lighting_lanes.cpp) must equal byte for byte, and that the lanes are written from.
LitPair light_both_reference(const GBuffers& gbuffers, const Environment& env, const Camera& camera,
                             const LightingOptions& options, bool keep_radiance = false);

// Radiance leaving one shading point towards v (unit vectors, world space).
glm::vec3 shade_point(const SurfaceLobes& lobes, float roughness, glm::vec3 n, glm::vec3 v, float occlusion,
                      glm::vec3 emissive, const Environment& env, const LightingOptions& options);

// Khronos PBR Neutral tone mapper (Khronos 3D Commerce, 2024): keeps base colours faithful up to
// 0.76 and compresses highlights towards white.
glm::vec3 khronos_pbr_neutral(glm::vec3 color);
// ACES filmic curve fit (Narkowicz 2015, "ACES Filmic Tone Mapping Curve").
glm::vec3 aces_fitted(glm::vec3 color);

// Exposure, tone map and the sRGB transfer function (IEC 61966-2-1), 8 bits, RGB interleaved.
void tone_map_srgb8(glm::vec3 radiance, const LightingOptions& options, std::uint8_t* rgb);
std::vector<std::uint8_t> to_srgb8(const HdrImage& image, const LightingOptions& options);

}  // namespace gltf_pbr::preview
