// light_both's eight-pixel lanes against the scalar reference they were written from: the same
// bytes and the same radiance bits, on real assets and on constructed extreme G-buffers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/asset.hpp"
#include "preview/preview.hpp"

namespace gltf_pbr::preview {
namespace {

// Byte-equal 8-bit images and bit-equal radiance (memcmp: a NaN or -0 must match too).
void expect_identical(const LitPair& lanes, const LitPair& reference, const std::string& what) {
  EXPECT_EQ(lanes.covered, reference.covered) << what;
  size_t differing = 0;
  for (size_t i = 0; i < reference.after.size(); ++i)
    differing += (lanes.after[i] != reference.after[i]) + (lanes.before[i] != reference.before[i]);
  EXPECT_EQ(differing, 0u) << what << ": 8-bit channels that differ";
  ASSERT_EQ(lanes.after_hdr.radiance.size(), reference.after_hdr.radiance.size()) << what;
  const size_t bytes = reference.after_hdr.radiance.size() * sizeof(glm::vec3);
  EXPECT_EQ(std::memcmp(lanes.after_hdr.radiance.data(), reference.after_hdr.radiance.data(), bytes), 0) << what;
  EXPECT_EQ(std::memcmp(lanes.before_hdr.radiance.data(), reference.before_hdr.radiance.data(), bytes), 0) << what;
  EXPECT_TRUE(
      std::equal(lanes.after_hdr.covered.begin(), lanes.after_hdr.covered.end(), reference.after_hdr.covered.begin()))
      << what;
}

// Every lighting option the pass branches on.
std::vector<std::pair<std::string, LightingOptions>> option_sets() {
  std::vector<std::pair<std::string, LightingOptions>> sets{{"default", LightingOptions{}}};
  LightingOptions o;
  o.legacy_reading_b = true, sets.emplace_back("reading B", o);
  o = {}, o.lobe = SpecularLobe::BlinnPhong, sets.emplace_back("Blinn-Phong", o);
  o = {}, o.sun = false, sets.emplace_back("no sun", o);
  o = {}, o.tone_map = ToneMap::Aces, o.exposure = 3.0f, sets.emplace_back("ACES x3", o);
  o = {}, o.tone_map = ToneMap::Clamp, o.exposure = 0.25f, sets.emplace_back("clamp x0.25", o);
  return sets;
}

TEST(LightingLanes, RealAssetsLightToTheReferencesBytesAtEveryOption) {
  // Widths that are not a multiple of eight: the last lanes of each row repeat its last pixel.
  for (const char* file :
       {"Avocado/specgloss/Avocado.gltf", "VC/specgloss/VC.gltf", "CesiumMilkTruck/specgloss/CesiumMilkTruck.gltf",
        "2CylinderEngine/specgloss/2CylinderEngine.gltf"}) {
    const Asset asset = load_asset(fs::path(GLTF_PBR_SHARED_DIR) / "assets" / file);
    Asset converted = asset;
    (void)convert(converted, PreviewOptions{}.convert);
    const Scene scene = build_scene(asset, converted);
    const Camera camera = frame_camera(scene.bounds, 35, 20, 40, 203.0 / 157.0);
    const GBuffers gbuffers = fill_gbuffers(scene, rasterize(scene, camera, 203, 157), camera);
    size_t covered = 0;
    for (float d : gbuffers.after.depth) covered += std::isfinite(d);
    ASSERT_GT(covered, 1000u) << file;
    for (const auto& [name, options] : option_sets())
      expect_identical(light_both(gbuffers, default_environment(), camera, options, true),
                       light_both_reference(gbuffers, default_environment(), camera, options, true),
                       std::string(file) + ", " + name);
  }
}

// Every normal the octahedral code can hold facing away from, along and across the view; every
// roughness and gloss code; black, white and out-of-range emission; occlusion; F0 from 0 to 1.
TEST(LightingLanes, ExtremeGBuffersLightToTheReferencesBits) {
  const int width = 61, height = 53;  // 61: seven full lanes and five in each row
  const size_t count = static_cast<size_t>(width) * height;
  GBuffers g;
  for (GBuffer* side : {&g.before, &g.after}) {
    side->width = width, side->height = height;
    side->depth.resize(count);
    side->normal.resize(count);
    side->emissive.resize(count);
    side->occlusion.resize(count);
  }
  g.after.albedo.resize(count);
  g.before.diffspec.resize(count);
  std::uint32_t state = 12345;
  auto next = [&] { return state = state * 1664525u + 1013904223u; };
  for (size_t i = 0; i < count; ++i) {
    const std::uint32_t r = next();
    // Some pixels empty (infinite and NaN depth), the rest covered.
    g.after.depth[i] = g.before.depth[i] = i % 7 == 0    ? std::numeric_limits<float>::infinity()
                                           : i % 11 == 0 ? std::numeric_limits<float>::quiet_NaN()
                                                         : 1.0f;
    const std::uint32_t normal = next() & 0xFFFFFFu;
    g.after.normal[i] = {normal | ((r & 255u) << 24)};
    g.before.normal[i] = {normal | (((r >> 8) & 255u) << 24)};
    const std::uint32_t colour = next();
    g.after.albedo[i] = {{static_cast<std::uint8_t>(colour), static_cast<std::uint8_t>(colour >> 8),
                          static_cast<std::uint8_t>(colour >> 16)},
                         static_cast<std::uint8_t>(colour >> 24)};
    const std::uint32_t specular = i % 5 == 0 ? 0xFFFFFFu : next();
    g.before.diffspec[i] = {{static_cast<std::uint8_t>(colour >> 24), static_cast<std::uint8_t>(colour >> 4),
                             static_cast<std::uint8_t>(colour >> 12)},
                            {static_cast<std::uint8_t>(specular), static_cast<std::uint8_t>(specular >> 8),
                             static_cast<std::uint8_t>(specular >> 16)}};
    const glm::vec3 emission = i % 3 == 0 ? glm::vec3(0.0f) : glm::vec3(next() % 1000, next() % 7, 65000.0f) * 0.01f;
    g.after.emissive[i] = g.before.emissive[i] = {pack_rgb9e5(emission)};
    g.after.occlusion[i] = g.before.occlusion[i] = static_cast<std::uint8_t>(r >> 16);
  }
  Camera camera = frame_camera(Bounds{glm::dvec3(-1), glm::dvec3(1)}, 10, 80, 120, static_cast<double>(width) / height);
  for (const auto& [name, options] : option_sets()) {
    expect_identical(light_both(g, default_environment(), camera, options, true),
                     light_both_reference(g, default_environment(), camera, options, true), name);
    const Environment furnace = uniform_environment(glm::vec3(1.0f));  // no sun, one radiance everywhere
    expect_identical(light_both(g, furnace, camera, options, true),
                     light_both_reference(g, furnace, camera, options, true), name + ", furnace");
  }
  camera.orthographic = true;  // every ray the same
  expect_identical(light_both(g, default_environment(), camera, LightingOptions{}, true),
                   light_both_reference(g, default_environment(), camera, LightingOptions{}, true), "orthographic");
}

}  // namespace
}  // namespace gltf_pbr::preview
