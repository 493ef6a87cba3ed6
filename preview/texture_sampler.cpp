// Footprint-shared trilinear sampling for the G-buffer pass (see texture_sampler.hpp).
#include "preview/texture_sampler.hpp"

#include <algorithm>
#include <cmath>

#include "core/color.hpp"
#include "preview/fast_math.hpp"

namespace gltf_pbr::preview {
namespace {

// glTF 2.0 section 5.26 sampler wrap modes (OpenGL enums).
constexpr int kRepeat = 10497, kClampToEdge = 33071, kMirroredRepeat = 33648;

// As scene.cpp: the coordinate folded into [0, 1] by the wrap mode.
inline float wrap_coordinate(float t, int mode) {
  if (mode == kClampToEdge) return std::clamp(t, 0.0f, 1.0f);
  if (mode == kMirroredRepeat) {
    const float period = t - 2.0f * floor_fast(t * 0.5f);
    return period > 1.0f ? 2.0f - period : period;
  }
  return t - floor_fast(t);
}

// As scene.cpp: taps of a folded coordinate fall in [-1, size], so one comparison wraps them.
inline int wrap_texel(int i, int size, int mode) {
  if (i < 0) return mode == kRepeat ? i + size : 0;
  if (i >= size) return mode == kRepeat ? i - size : size - 1;
  return i;
}

// Taps of one level: OpenGL 4.6 section 8.14.2 (texel centres at +0.5, weights 1 - frac, frac),
// or the nearest texel (all weight on the first tap) for magFilter NEAREST.
void level_taps(const TextureSlot& slot, int width, int height, glm::vec2 wrapped, float level_weight,
                std::size_t offset[4], float weight[4]) {
  const float u = wrapped.x * static_cast<float>(width) - 0.5f;
  const float v = wrapped.y * static_cast<float>(height) - 0.5f;
  const std::size_t stride = static_cast<std::size_t>(width) * 4;
  if (slot.nearest) {
    const int x = wrap_texel(static_cast<int>(floor_fast(u + 0.5f)), width, slot.wrap_s);
    const int y = wrap_texel(static_cast<int>(floor_fast(v + 0.5f)), height, slot.wrap_t);
    const std::size_t at = static_cast<std::size_t>(y) * stride + static_cast<std::size_t>(x) * 4;
    for (int k = 0; k < 4; ++k) offset[k] = at, weight[k] = k == 0 ? level_weight : 0.0f;
    return;
  }
  const float fx = floor_fast(u), fy = floor_fast(v);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const float tx = u - fx, ty = v - fy;
  const std::size_t column0 = static_cast<std::size_t>(wrap_texel(x0, width, slot.wrap_s)) * 4;
  const std::size_t column1 = static_cast<std::size_t>(wrap_texel(x0 + 1, width, slot.wrap_s)) * 4;
  const std::size_t row0 = static_cast<std::size_t>(wrap_texel(y0, height, slot.wrap_t)) * stride;
  const std::size_t row1 = static_cast<std::size_t>(wrap_texel(y0 + 1, height, slot.wrap_t)) * stride;
  offset[0] = row0 + column0, offset[1] = row0 + column1, offset[2] = row1 + column0, offset[3] = row1 + column1;
  weight[0] = (1.0f - tx) * (1.0f - ty) * level_weight, weight[1] = tx * (1.0f - ty) * level_weight;
  weight[2] = (1.0f - tx) * ty * level_weight, weight[3] = tx * ty * level_weight;
}

bool same_footprint(const TextureSlot& a, const TextureSlot& b) {
  return a.tex_coord == b.tex_coord && a.texture->width == b.texture->width && a.texture->height == b.texture->height &&
         a.texture->mips.size() == b.texture->mips.size() && a.wrap_s == b.wrap_s && a.wrap_t == b.wrap_t &&
         a.nearest == b.nearest && a.has_transform == b.has_transform &&
         (!a.has_transform || (a.row_u == b.row_u && a.row_v == b.row_v));
}

}  // namespace

// 8-bit code -> float, as scene.cpp's decode_texel computes it: sRGB through core's table
// (IEC 61966-2-1), linear as code / 255.
const TexelDecodeTables kTexelDecode = [] {
  TexelDecodeTables tables;
  const auto& srgb = srgb8_to_linear_table();
  for (int i = 0; i < 256; ++i) {
    tables.srgb[i] = srgb[static_cast<std::size_t>(i)];
    tables.linear[i] = static_cast<float>(i) * (1.0f / 255.0f);
  }
  return tables;
}();

const TextureSlot& slot_of(const PreviewMaterial& m, MaterialSlot slot) {
  switch (slot) {
    case kNormalSlot:
      return m.normal_texture;
    case kOcclusionSlot:
      return m.occlusion_texture;
    case kEmissiveSlot:
      return m.emissive_texture;
    case kBaseColorSlot:
      return m.base_color_texture;
    case kMetallicRoughnessSlot:
      return m.metallic_roughness_texture;
    case kDiffuseSlot:
      return m.diffuse_texture;
    case kSpecGlossSlot:
      return m.spec_gloss_texture;
    case kOriginalBaseColorSlot:
      return m.original_base_color_texture;
    case kOriginalMetallicRoughnessSlot:
      return m.original_metallic_roughness_texture;
  }
  return m.normal_texture;
}

MaterialSamplingPlan plan_sampling(const PreviewMaterial& material) {
  MaterialSamplingPlan plan;
  plan.group.fill(-1);
  for (int s = 0; s < MaterialSamplingPlan::kSlots; ++s) {
    const TextureSlot& slot = slot_of(material, static_cast<MaterialSlot>(s));
    if (!slot) continue;
    plan.textured = true;
    int group = 0;
    while (group < plan.group_count && !same_footprint(*plan.group_source[static_cast<std::size_t>(group)], slot))
      ++group;
    if (group == plan.group_count) plan.group_source[static_cast<std::size_t>(plan.group_count++)] = &slot;
    plan.group[static_cast<std::size_t>(s)] = group;
  }
  return plan;
}

Footprint footprint_of(const TextureSlot& slot, const glm::vec2 uv_sets[2], const UvDerivatives* derivatives) {
  // scene.cpp `sample`, step by step: where the slot reads, then taps of one or two levels.
  const Texture& texture = *slot.texture;
  const SlotLookup lookup = slot_lookup(slot, uv_sets, derivatives);
  const glm::vec2 uv = lookup.uv;
  const float lod = lookup.lod;
  const glm::vec2 wrapped(wrap_coordinate(uv.x, slot.wrap_s), wrap_coordinate(uv.y, slot.wrap_t));
  const int l0 = static_cast<int>(lod);
  const float t = lod - static_cast<float>(l0);
  const bool blend = t > 0.0f && l0 < static_cast<int>(texture.mips.size());
  Footprint f;
  f.level_count = blend ? 2 : 1;
  for (int k = 0; k < f.level_count; ++k) {
    const int level = l0 + k;
    f.level[k] = level;
    const int width = level == 0 ? texture.width : texture.mips[static_cast<std::size_t>(level - 1)].width;
    const int height = level == 0 ? texture.height : texture.mips[static_cast<std::size_t>(level - 1)].height;
    level_taps(slot, width, height, wrapped, blend ? (k == 0 ? 1.0f - t : t) : 1.0f, f.offset[k], f.weight[k]);
  }
  return f;
}

}  // namespace gltf_pbr::preview
