// Footprint-shared trilinear sampling for the G-buffer pass (see texture_sampler.hpp).
#include "preview/texture_sampler.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/color.hpp"
#include "preview/fast_math.hpp"

namespace gltf_pbr::preview {
namespace {

// glTF 2.0 section 5.26 sampler wrap modes (OpenGL enums).
constexpr int kRepeat = 10497, kClampToEdge = 33071, kMirroredRepeat = 33648;

// The coordinate folded into [0, 1] by the wrap mode (floor_fast is exact: the same as std::floor).
inline float wrap_coordinate(float t, int mode) {
  if (mode == kClampToEdge) return std::clamp(t, 0.0f, 1.0f);
  if (mode == kMirroredRepeat) {
    const float period = t - 2.0f * floor_fast(t * 0.5f);
    return period > 1.0f ? 2.0f - period : period;
  }
  return t - floor_fast(t);
}

// Texel index for bilinear taps: a folded coordinate's taps fall in [-1, size], so one comparison
// wraps them (no integer division).
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
         a.texture->mips.size() == b.texture->mips.size() && a.texture->first_level == b.texture->first_level &&
         a.wrap_s == b.wrap_s && a.wrap_t == b.wrap_t && a.nearest == b.nearest && a.has_transform == b.has_transform &&
         (!a.has_transform || (a.row_u == b.row_u && a.row_v == b.row_v));
}

}  // namespace

// 8-bit code -> float, as decode_texel (the scalar reference, below) computes it: sRGB through core's table
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
  // `sample` (below), step by step: where the slot reads, then taps of one or two levels.
  const Texture& texture = *slot.texture;
  const SlotLookup lookup = slot_lookup(slot, uv_sets, derivatives);
  const glm::vec2 uv = lookup.uv;
  const float lod = lookup.lod;
  const glm::vec2 wrapped(wrap_coordinate(uv.x, slot.wrap_s), wrap_coordinate(uv.y, slot.wrap_t));
  // Below first_level only if a footprint disagreed with finest_sampled_levels': its level, then.
  const int l0 = std::max(static_cast<int>(lod), texture.first_level);
  const float t = l0 == static_cast<int>(lod) ? lod - static_cast<float>(l0) : 0.0f;
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

// ---- The scalar reference: one texture sample at a time (scene.hpp `sample`).

namespace {

// One level from the one above: a 2 x 2 box (an odd last row or column repeats), rounded to
// nearest. `texel(x, y)` gives the RGBA8 bytes of the level above.
template <typename TexelOf>
TextureLevel half_level(int w, int h, const TexelOf& texel) {
  TextureLevel level{std::max(1, w / 2), std::max(1, h / 2), {}};
  level.rgba.resize(static_cast<size_t>(level.width) * static_cast<size_t>(level.height) * 4);
  std::uint8_t* out = level.rgba.data();
  for (int y = 0; y < level.height; ++y) {
    const int y0 = std::min(2 * y, h - 1), y1 = std::min(2 * y + 1, h - 1);
    for (int x = 0; x < level.width; ++x, out += 4) {
      const int x0 = std::min(2 * x, w - 1), x1 = std::min(2 * x + 1, w - 1);
      const auto a = texel(x0, y0), b = texel(x1, y0), c = texel(x0, y1), d = texel(x1, y1);
      for (int k = 0; k < 4; ++k) out[k] = static_cast<std::uint8_t>((a[k] + b[k] + c[k] + d[k] + 2) / 4);
    }
  }
  return level;
}

// RGBA8 texel `p` of any decoded image: grey expanded to RGB, a missing alpha opaque, wider
// samples rounded.
std::array<std::uint8_t, 4> rgba8_texel(const Pixels& pixels, size_t p) {
  const size_t ch = static_cast<size_t>(pixels.channels), in = p * ch;
  auto channel = [&](size_t i) -> std::uint8_t {
    if (!pixels.bytes.empty()) return pixels.bytes[i];
    return static_cast<std::uint8_t>(std::clamp(pixels.value(i), 0.0f, 1.0f) * 255.0f + 0.5f);
  };
  if (ch <= 2) {
    const std::uint8_t grey = channel(in);
    return {grey, grey, grey, ch == 2 ? channel(in + 1) : std::uint8_t{255}};
  }
  return {channel(in), channel(in + 1), channel(in + 2), ch >= 4 ? channel(in + 3) : std::uint8_t{255}};
}

// 8-bit RGBA of a whole decoded image (8-bit RGBA bytes as they are).
TexelBytes rgba8_of(const Pixels& pixels) {
  const size_t count = static_cast<size_t>(pixels.width) * static_cast<size_t>(pixels.height);
  TexelBytes rgba(count * 4);
  if (pixels.channels == 4 && !pixels.bytes.empty()) {
    std::copy(pixels.bytes.begin(), pixels.bytes.end(), rgba.begin());
    return rgba;
  }
  for (size_t p = 0; p < count; ++p) {
    const auto texel = rgba8_texel(pixels, p);
    std::copy(texel.begin(), texel.end(), rgba.data() + p * 4);
  }
  return rgba;
}

}  // namespace

void Texture::size_levels(int level0_width, int level0_height) {
  width = level0_width, height = level0_height;
  rgba.clear();
  mips.clear();
  for (int w = width, h = height; w > 1 || h > 1;) {
    w = std::max(1, w / 2), h = std::max(1, h / 2);
    mips.push_back({w, h, {}});
  }
}

void Texture::build_mips() {
  first_level = 0;
  mips.clear();
  int w = width, h = height;
  const TexelBytes* source = &rgba;
  while (w > 1 || h > 1) {
    const std::uint8_t* above = source->data();
    const size_t stride = static_cast<size_t>(w);
    mips.push_back(half_level(w, h, [&](int x, int y) {
      const std::uint8_t* t = above + (static_cast<size_t>(y) * stride + static_cast<size_t>(x)) * 4;
      return std::array<std::uint8_t, 4>{t[0], t[1], t[2], t[3]};
    }));
    w = mips.back().width, h = mips.back().height;
    source = &mips.back().rgba;
  }
}

void Texture::build_levels(const Pixels& source, int first) {
  size_levels(source.width, source.height);
  first_level = std::clamp(first, 0, static_cast<int>(mips.size()));
  if (first_level == 0) {
    rgba = rgba8_of(source);
    build_mips();
    return;
  }
  // Level 1 straight from the decoded pixels (the same bytes as from rgba8_of's level 0), then
  // each level from the one before; those above first_level are dropped once used.
  const size_t stride = static_cast<size_t>(width);
  mips[0] = half_level(width, height, [&](int x, int y) {
    return rgba8_texel(source, static_cast<size_t>(y) * stride + static_cast<size_t>(x));
  });
  for (size_t level = 1; level < mips.size(); ++level) {
    const TextureLevel& above = mips[level - 1];
    const std::uint8_t* texels = above.rgba.data();
    const size_t above_stride = static_cast<size_t>(above.width);
    mips[level] = half_level(above.width, above.height, [&](int x, int y) {
      const std::uint8_t* t = texels + (static_cast<size_t>(y) * above_stride + static_cast<size_t>(x)) * 4;
      return std::array<std::uint8_t, 4>{t[0], t[1], t[2], t[3]};
    });
    if (static_cast<int>(level) < first_level) TexelBytes().swap(mips[level - 1].rgba);  // level `level` is not kept
  }
}

namespace {

[[gnu::always_inline]] inline glm::vec4 decode_texel(const std::uint8_t* t, const float* srgb_lut) {
  if (srgb_lut) return {srgb_lut[t[0]], srgb_lut[t[1]], srgb_lut[t[2]], static_cast<float>(t[3]) * (1.0f / 255.0f)};
  return glm::vec4(t[0], t[1], t[2], t[3]) * (1.0f / 255.0f);
}

glm::vec4 sample_level(const TextureSlot& slot, const std::uint8_t* texels, int width, int height, glm::vec2 uv) {
  static const float* const srgb_lut = srgb8_to_linear_table().data();
  const float* lut = slot.srgb ? srgb_lut : nullptr;
  const float u = wrap_coordinate(uv.x, slot.wrap_s) * static_cast<float>(width) - 0.5f;
  const float v = wrap_coordinate(uv.y, slot.wrap_t) * static_cast<float>(height) - 0.5f;
  const size_t stride = static_cast<size_t>(width) * 4;
  if (slot.nearest) {
    const int x = wrap_texel(static_cast<int>(floor_fast(u + 0.5f)), width, slot.wrap_s);
    const int y = wrap_texel(static_cast<int>(floor_fast(v + 0.5f)), height, slot.wrap_t);
    return decode_texel(texels + static_cast<size_t>(y) * stride + static_cast<size_t>(x) * 4, lut);
  }
  const float fx = floor_fast(u), fy = floor_fast(v);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const float tx = u - fx, ty = v - fy;
  const size_t column0 = static_cast<size_t>(wrap_texel(x0, width, slot.wrap_s)) * 4;
  const size_t column1 = static_cast<size_t>(wrap_texel(x0 + 1, width, slot.wrap_s)) * 4;
  const std::uint8_t* row0 = texels + static_cast<size_t>(wrap_texel(y0, height, slot.wrap_t)) * stride;
  const std::uint8_t* row1 = texels + static_cast<size_t>(wrap_texel(y0 + 1, height, slot.wrap_t)) * stride;
  const glm::vec4 top = glm::mix(decode_texel(row0 + column0, lut), decode_texel(row0 + column1, lut), tx);
  const glm::vec4 bottom = glm::mix(decode_texel(row1 + column0, lut), decode_texel(row1 + column1, lut), tx);
  return glm::mix(top, bottom, ty);
}

}  // namespace

SlotLookup slot_lookup(const TextureSlot& slot, const glm::vec2 uv_sets[2], const UvDerivatives* derivatives) {
  const Texture& texture = *slot.texture;
  SlotLookup lookup{uv_sets[slot.tex_coord]};
  auto transform_linear = [&](glm::vec2 d) {
    return slot.has_transform
               ? glm::vec2(slot.row_u.x * d.x + slot.row_u.y * d.y, slot.row_v.x * d.x + slot.row_v.y * d.y)
               : d;
  };
  glm::vec2& uv = lookup.uv;
  if (slot.has_transform)  // rows of the affine matrix
    uv = glm::vec2(slot.row_u.x * uv.x + slot.row_u.y * uv.y + slot.row_u.z,
                   slot.row_v.x * uv.x + slot.row_v.y * uv.y + slot.row_v.z);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
  if (derivatives && !texture.mips.empty()) {
    const glm::vec2 size(static_cast<float>(texture.width), static_cast<float>(texture.height));
    const glm::vec2 dx = transform_linear(derivatives->dx[slot.tex_coord]) * size;
    const glm::vec2 dy = transform_linear(derivatives->dy[slot.tex_coord]) * size;
    const float rho2 = std::max(dx.x * dx.x + dx.y * dx.y, dy.x * dy.x + dy.y * dy.y);
    if (rho2 > 1.0f && std::isfinite(rho2))
      lookup.lod = std::min(0.5f * std::log2(rho2), static_cast<float>(texture.mips.size()));
  }
  return lookup;
}

glm::vec4 sample(const TextureSlot& slot, const glm::vec2 uv_sets[2], const UvDerivatives* derivatives) {
  const Texture& texture = *slot.texture;
  const SlotLookup lookup = slot_lookup(slot, uv_sets, derivatives);
  const glm::vec2 uv = lookup.uv;  // named, not a structured binding: clang 14 lambdas cannot capture those
  const float lod = lookup.lod;
  auto level = [&](int l) {
    if (l == 0) return sample_level(slot, texture.rgba.data(), texture.width, texture.height, uv);
    const TextureLevel& m = texture.mips[static_cast<size_t>(l - 1)];
    return sample_level(slot, m.rgba.data(), m.width, m.height, uv);
  };
  const int l0 = std::max(static_cast<int>(lod), texture.first_level);  // (as footprint_of)
  const float t = l0 == static_cast<int>(lod) ? lod - static_cast<float>(l0) : 0.0f;
  const glm::vec4 a = level(l0);
  return t > 0.0f && l0 < static_cast<int>(texture.mips.size()) ? glm::mix(a, level(l0 + 1), t) : a;
}

}  // namespace gltf_pbr::preview
