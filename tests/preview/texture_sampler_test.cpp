// The G-buffer pass's footprint-shared sampler against its scalar reference, scene.hpp `sample`.
#include "preview/texture_sampler.hpp"

#include <gtest/gtest.h>

#include <random>

namespace gltf_pbr::preview {
namespace {

Texture random_texture(int width, int height, std::mt19937& rng) {
  Texture t;
  t.width = width;
  t.height = height;
  t.rgba.resize(static_cast<size_t>(width) * static_cast<size_t>(height) * 4);
  std::uniform_int_distribution<int> byte(0, 255);
  for (auto& v : t.rgba) v = static_cast<std::uint8_t>(byte(rng));
  t.build_mips();
  return t;
}

TEST(TextureSampler, MatchesSceneSampleAcrossWrapModesTransformsAndFootprints) {
  std::mt19937 rng(7);
  const Texture textures[] = {random_texture(64, 64, rng), random_texture(37, 12, rng), random_texture(1, 1, rng)};
  std::uniform_real_distribution<float> uv(-3.0f, 3.0f), step(-0.2f, 0.2f), tiny(-0.002f, 0.002f);
  const int wraps[] = {10497, 33071, 33648};
  int compared = 0;
  for (const Texture& texture : textures)
    for (int wrap_s : wraps)
      for (int wrap_t : wraps)
        for (int variant = 0; variant < 8; ++variant) {
          TextureSlot slot;
          slot.texture = &texture;
          slot.tex_coord = variant & 1;
          slot.srgb = (variant & 2) != 0;
          slot.nearest = variant == 4;
          slot.wrap_s = wrap_s, slot.wrap_t = wrap_t;
          if (variant >= 5) {  // KHR_texture_transform: rotation, scale, offset
            slot.has_transform = true;
            slot.row_u = glm::vec3(0.8f, -0.6f, 0.25f) * (variant == 6 ? 2.0f : 1.0f);
            slot.row_v = glm::vec3(0.6f, 0.8f, -0.5f);
          }
          for (int i = 0; i < 40; ++i) {
            const glm::vec2 sets[2] = {{uv(rng), uv(rng)}, {uv(rng), uv(rng)}};
            UvDerivatives d;
            const bool minified = i % 2 == 0;  // alternate minification and magnification
            for (int s = 0; s < 2; ++s) {
              d.dx[s] = minified ? glm::vec2(step(rng), step(rng)) : glm::vec2(tiny(rng), tiny(rng));
              d.dy[s] = minified ? glm::vec2(step(rng), step(rng)) : glm::vec2(tiny(rng), tiny(rng));
            }
            const glm::vec4 expected = sample(slot, sets, &d);
            const Footprint footprint = footprint_of(slot, sets, &d);
            const glm::vec4 scalar = fetch_scalar(texture, footprint, slot.srgb);
            const glm::vec4 simd = fetch(texture, footprint, slot.srgb);
            for (int c = 0; c < 4; ++c) {
              ASSERT_NEAR(scalar[c], expected[c], 2e-6f) << c << " " << variant << " " << i;
              ASSERT_NEAR(simd[c], expected[c], 2e-6f) << c << " " << variant << " " << i;
            }
            ++compared;
          }
        }
  EXPECT_EQ(compared, 3 * 9 * 8 * 40);
}

TEST(TextureSampler, GroupsSlotsThatShareAFootprint) {
  std::mt19937 rng(3);
  const Texture a = random_texture(16, 16, rng), b = random_texture(16, 16, rng), c = random_texture(8, 8, rng);
  PreviewMaterial m;
  m.base_color_texture = {&a, 0, true};
  m.metallic_roughness_texture = {&b, 0, false};  // same size, set, sampler: shares
  m.normal_texture = {&c, 0, false};              // other size: own group
  m.diffuse_texture = {&a, 1, true};              // other UV set: own group
  const MaterialSamplingPlan plan = plan_sampling(m);
  EXPECT_TRUE(plan.textured);
  EXPECT_EQ(plan.group_count, 3);
  EXPECT_EQ(plan.group[kBaseColorSlot], plan.group[kMetallicRoughnessSlot]);
  EXPECT_NE(plan.group[kBaseColorSlot], plan.group[kNormalSlot]);
  EXPECT_NE(plan.group[kBaseColorSlot], plan.group[kDiffuseSlot]);
  EXPECT_EQ(plan.group[kEmissiveSlot], -1);
  EXPECT_FALSE(plan_sampling(PreviewMaterial{}).textured);
}

}  // namespace
}  // namespace gltf_pbr::preview
