// The G-buffer pass's texture sampler: the same trilinear filter as scene.hpp `sample` (its scalar
// reference, defined beside it in texture_sampler.cpp and compared in
// tests/preview/texture_sampler_test.cpp), restructured for a pixel that reads five or six
// textures. Texture coordinates, the mip level (a log2) and the eight tap addresses and weights are
// computed once per *footprint group*, the slots of a material that share a UV set, level-0 size,
// sampler and KHR_texture_transform, and reused for every texture of the group (an asset's textures
// are usually all the same size on UV set 0). The fetch then reads 8-bit texels directly: a
// 256-entry table decodes sRGB, a multiply converts linear channels.
#pragma once
#include <array>
#include <cstdint>
#include <cstring>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <vector>

#include "preview/scene.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace gltf_pbr::preview {

// Where the taps of one trilinear (or nearest) sample fall, as byte offsets into each level's
// RGBA8 texels, and their weights (bilinear weights times the level blend; they sum to 1).
// Trivial on purpose: a pixel keeps nine of them and fills only those it uses.
struct Footprint {
  int level[2];              // mip levels read (0 = Texture::rgba)
  int level_count;           // 1, or 2 when blending into the next level
  std::size_t offset[2][4];  // per level: taps (x0,y0), (x1,y0), (x0,y1), (x1,y1)
  float weight[2][4];
};

// Per material: which footprint group each texture slot belongs to (-1: no texture).
struct MaterialSamplingPlan {
  static constexpr int kSlots = 9;
  std::array<int, kSlots> group{};
  std::array<const TextureSlot*, kSlots> group_source{};  // a representative slot of each group
  int group_count = 0;
  bool textured = false;
};

// Slot order of MaterialSamplingPlan::group.
enum MaterialSlot : int {
  kNormalSlot,
  kOcclusionSlot,
  kEmissiveSlot,
  kBaseColorSlot,
  kMetallicRoughnessSlot,
  kDiffuseSlot,
  kSpecGlossSlot,
  kOriginalBaseColorSlot,
  kOriginalMetallicRoughnessSlot
};
const TextureSlot& slot_of(const PreviewMaterial& material, MaterialSlot slot);

MaterialSamplingPlan plan_sampling(const PreviewMaterial& material);

// The footprint of `slot` at a pixel (`sample`: KHR_texture_transform, wrap modes,
// OpenGL 4.6 section 8.14.1 level of detail, section 8.14.2 bilinear taps).
Footprint footprint_of(const TextureSlot& slot, const glm::vec2 uv_sets[2], const UvDerivatives* derivatives);

struct TexelDecodeTables {
  float srgb[256], linear[256];
};
extern const TexelDecodeTables kTexelDecode;

inline const std::uint8_t* level_texels(const Texture& texture, int level) {
  return level == 0 ? texture.rgba.data() : texture.mips[static_cast<std::size_t>(level - 1)].rgba.data();
}

// Weighted sum of the footprint's taps in `texture`, RGB decoded from sRGB when `srgb` (alpha is
// always linear). The scalar reference; `fetch` below is the same sum four channels at a time.
inline glm::vec4 fetch_scalar(const Texture& texture, const Footprint& f, bool srgb) {
  const float* rgb_table = srgb ? kTexelDecode.srgb : kTexelDecode.linear;
  const float* alpha_table = kTexelDecode.linear;
  float r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f;
  for (int k = 0; k < f.level_count; ++k) {
    const std::uint8_t* texels = level_texels(texture, f.level[k]);
    for (int tap = 0; tap < 4; ++tap) {
      const std::uint8_t* t = texels + f.offset[k][tap];
      const float w = f.weight[k][tap];
      r += w * rgb_table[t[0]];
      g += w * rgb_table[t[1]];
      b += w * rgb_table[t[2]];
      a += w * alpha_table[t[3]];
    }
  }
  return {r, g, b, a};
}

#if defined(__SSE2__)
// SSE2 (the x86-64 baseline): one RGBA tap is one 4-lane multiply-add. Linear textures widen the
// four bytes to floats in registers and scale by 1/255 once at the end; sRGB textures read the
// table per colour channel. Agrees with fetch_scalar to float rounding (texture_sampler_test).
inline glm::vec4 fetch(const Texture& texture, const Footprint& f, bool srgb) {
  __m128 sum = _mm_setzero_ps();
  if (srgb) {
    const float* table = kTexelDecode.srgb;
    for (int k = 0; k < f.level_count; ++k) {
      const std::uint8_t* texels = level_texels(texture, f.level[k]);
      for (int tap = 0; tap < 4; ++tap) {
        const std::uint8_t* t = texels + f.offset[k][tap];
        const __m128 texel = _mm_setr_ps(table[t[0]], table[t[1]], table[t[2]], kTexelDecode.linear[t[3]]);
        sum = _mm_add_ps(sum, _mm_mul_ps(texel, _mm_set1_ps(f.weight[k][tap])));
      }
    }
  } else {
    const __m128i zero = _mm_setzero_si128();
    for (int k = 0; k < f.level_count; ++k) {
      const std::uint8_t* texels = level_texels(texture, f.level[k]);
      for (int tap = 0; tap < 4; ++tap) {
        std::int32_t rgba;
        std::memcpy(&rgba, texels + f.offset[k][tap], 4);
        const __m128i bytes = _mm_cvtsi32_si128(rgba);
        const __m128i words = _mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, zero), zero);
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_cvtepi32_ps(words), _mm_set1_ps(f.weight[k][tap])));
      }
    }
    sum = _mm_mul_ps(sum, _mm_set1_ps(1.0f / 255.0f));
  }
  alignas(16) float lanes[4];
  _mm_store_ps(lanes, sum);
  return {lanes[0], lanes[1], lanes[2], lanes[3]};
}
#else
inline glm::vec4 fetch(const Texture& texture, const Footprint& f, bool srgb) { return fetch_scalar(texture, f, srgb); }
#endif

// One pixel's sampler over a material: footprints computed on first use, shared by their group.
class PixelSampler {
 public:
  PixelSampler(const MaterialSamplingPlan& plan, const glm::vec2 uv_sets[2], const UvDerivatives* derivatives)
      : plan_(plan), uv_sets_(uv_sets), derivatives_(derivatives) {}
  glm::vec4 operator()(const TextureSlot& slot, MaterialSlot which) {
    const int group = plan_.group[static_cast<std::size_t>(which)];
    const auto g = static_cast<std::size_t>(group);
    if (!(ready_ & (1u << group))) {
      footprints_[g] = footprint_of(*plan_.group_source[g], uv_sets_, derivatives_);
      ready_ |= 1u << group;
    }
    return fetch(*slot.texture, footprints_[g], slot.srgb);
  }

 private:
  const MaterialSamplingPlan& plan_;
  const glm::vec2* uv_sets_;
  const UvDerivatives* derivatives_;
  std::uint32_t ready_ = 0;
  std::array<Footprint, MaterialSamplingPlan::kSlots> footprints_;
};

}  // namespace gltf_pbr::preview
