// Packed G-buffer texels of the two shading models (DESIGN.md, "Preview renderer"). The "after"
// model needs 4 channels for its material (albedo + metalness); the legacy "before" model needs 7
// (diffuse + specular colour + gloss). Channels the scene does not use get no buffer.
#pragma once
#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <type_traits>
#include <vector>

#include "core/texel_buffer.hpp"

namespace gltf_pbr::preview {

// Octahedral unit-vector encoding (Cigolle et al. 2014, "A Survey of Efficient Representations
// for Independent Unit Vectors", section 3.3), 12 bits per axis: under 0.05 degrees of error.
std::uint32_t pack_octahedral_12_12(glm::vec3 unit);
glm::vec3 unpack_octahedral_12_12(std::uint32_t bits);

// 8-bit sRGB (IEC 61966-2-1) through tables: the transfer function's pow costs more than the
// rest of a G-buffer texel. Encoding quantises the linear value to 65536 steps (under 0.1 level
// of error) and finds the code whose interval holds it: the code at the start of its 16-step
// bucket, plus one where the bucket holds the next code's first step. Codes are at least 19.9
// steps apart (the transfer's steepest part, slope 12.92), so a bucket holds at most one; the
// two tables (5 KB) stay in the L1 cache where one byte a step (64 KB) did not, and the
// function inlines into the G-buffer and lighting loops that call it for every pixel.
struct SrgbEncodeTables {
  std::array<std::uint8_t, 4096> bucket_code;  // the code of step 16 b
  std::array<std::uint32_t, 257> first_step;   // first_step[k]: the first step encoded as k (256: none)
};
extern const SrgbEncodeTables kSrgbEncode;
inline std::uint8_t encode_srgb8(float linear) {
  const float clamped = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) : 0.0f;  // NaN -> 0
  const auto step = static_cast<std::uint32_t>(clamped * 65535.0f + 0.5f);
  const std::uint32_t code = kSrgbEncode.bucket_code[step >> 4];
  return static_cast<std::uint8_t>(code + (step >= kSrgbEncode.first_step[code + 1] ? 1u : 0u));
}
float decode_srgb8(std::uint8_t encoded);

// RGB9E5 shared-exponent HDR colour (OpenGL EXT_texture_shared_exponent): emissive > 1 fits in 4 bytes.
std::uint32_t pack_rgb9e5(glm::vec3 rgb);
glm::vec3 unpack_rgb9e5(std::uint32_t bits);

// "after": albedo (sRGB-encoded, 8 bits) + metalness (linear, 8 bits).
struct AlbedoMetalness {
  std::uint8_t albedo_srgb[3];
  std::uint8_t metalness;
};
static_assert(sizeof(AlbedoMetalness) == 4 && std::is_trivially_copyable_v<AlbedoMetalness>);

// Octahedral normal (12 + 12 bits) + an 8-bit scalar: roughness ("after") or gloss ("before").
struct NormalAndScalar {
  std::uint32_t bits;  // [0,12) normal u, [12,24) normal v, [24,32) scalar
};
static_assert(sizeof(NormalAndScalar) == 4 && std::is_trivially_copyable_v<NormalAndScalar>);
NormalAndScalar pack_normal_and_scalar(glm::vec3 unit_normal, float scalar01);
glm::vec3 normal_of(NormalAndScalar packed);
float scalar_of(NormalAndScalar packed);

// "before": diffuse + specular colour, both sRGB-encoded 8 bits (6 channels).
struct DiffuseSpecular {
  std::uint8_t diffuse_srgb[3];
  std::uint8_t specular_srgb[3];
};
static_assert(sizeof(DiffuseSpecular) == 6 && std::is_trivially_copyable_v<DiffuseSpecular>);

// Shared by both sides, only when the scene has them.
struct Emissive {
  std::uint32_t rgb9e5;
};
static_assert(sizeof(Emissive) == 4);
using Occlusion = std::uint8_t;
using Depth = float;  // view-space distance along the axis; +inf where nothing was drawn

struct BufferSize {
  std::string name;
  int bytes_per_pixel = 0;
};

// One side's G-buffer. Vectors that the scene does not need stay empty.
struct GBuffer {
  int width = 0, height = 0;
  TexelBuffer<Depth> depth;
  TexelBuffer<NormalAndScalar> normal;     // + roughness (after) or gloss (before)
  TexelBuffer<AlbedoMetalness> albedo;     // after only
  TexelBuffer<DiffuseSpecular> diffspec;   // before only
  TexelBuffer<Emissive> emissive;          // when something emits
  TexelBuffer<Occlusion> occlusion;        // when a material has an occlusion texture
  std::vector<BufferSize> layout() const;  // what is allocated, bytes per pixel each
  int bytes_per_pixel() const;
};

}  // namespace gltf_pbr::preview

#include "preview/raster.hpp"

namespace gltf_pbr::preview {

struct GBuffers {
  GBuffer before, after;
};

// Resolves the visibility buffer through both sides' materials: normal mapping, vertex colours,
// texture sets and transforms, occlusion and emission.
GBuffers fill_gbuffers(const Scene& scene, const VisibilityBuffer& visibility, const Camera& camera);

// For each texture of scene.textures, the finest mip level fill_gbuffers samples at any pixel of
// `visibility` (the footprints it computes, for every slot of each pixel's material), or
// kUnsampled: what load_textures needs to keep (TextureLoading::SampledLevelsLater).
std::vector<int> finest_sampled_levels(const Scene& scene, const VisibilityBuffer& visibility, const Camera& camera);

// Unpacked texel of either side, as lighting reads it.
struct GBufferTexel {
  bool covered = false;
  glm::vec3 normal{0, 0, 1};
  float scalar = 0;                  // roughness (after) or gloss (before)
  glm::vec3 color_a{0}, color_b{0};  // after: albedo, (metalness, 0, 0); before: diffuse, specular
  glm::vec3 emissive{0};
  float occlusion = 1;
};
GBufferTexel read_after(const GBuffer& buffer, size_t pixel);
GBufferTexel read_before(const GBuffer& buffer, size_t pixel);
// read_before without unpacking the normal, for a pass that has it from the "after" side.
GBufferTexel read_before_material(const GBuffer& buffer, size_t pixel);

}  // namespace gltf_pbr::preview
