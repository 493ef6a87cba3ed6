// light_both's eight-pixel lanes against the scalar reference they were written from: the same
// bytes and the same radiance bits, on real assets and on constructed extreme G-buffers. A GCC
// build runs the lanes' AVX2 clone where the processor has AVX2; the sanitizer build (clang, no
// clones) runs the plain x86-64 lanes.
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
  EXPECT_EQ(lanes.after_hdr.covered, reference.after_hdr.covered) << what;
  EXPECT_EQ(lanes.before_hdr.covered, reference.before_hdr.covered) << what;
}

// Both passes with and without the radiance kept: the 8-bit images may not depend on it.
void expect_identical_passes(const GBuffers& g, const Environment& env, const Camera& camera,
                             const LightingOptions& options, const std::string& what) {
  const LitPair reference = light_both_reference(g, env, camera, options, true);
  expect_identical(light_both(g, env, camera, options, true), reference, what);
  const LitPair without_radiance = light_both(g, env, camera, options, false);
  EXPECT_TRUE(without_radiance.after_hdr.radiance.empty()) << what;
  EXPECT_EQ(without_radiance.after, reference.after) << what << ", radiance not kept";
  EXPECT_EQ(without_radiance.before, reference.before) << what << ", radiance not kept";
  EXPECT_EQ(without_radiance.covered, reference.covered) << what << ", radiance not kept";
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
      expect_identical_passes(gbuffers, default_environment(), camera, options, std::string(file) + ", " + name);
  }
}

// Random octahedral normals (facing away from, along and across the view), every roughness and
// gloss code, specular 1, emission from 0 to the format's top, occlusion, empty pixels (infinite
// and NaN depth, and whole groups of eight), a "before" side that drew nothing where "after" did,
// under the sky, a white furnace and a light so bright that the sum is not finite.
GBuffers extreme_gbuffers(int width, int height) {
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
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
    const bool sky = i % 7 == 0 || i < 2 * static_cast<size_t>(width);  // the first two rows: only sky
    g.after.depth[i] = sky           ? std::numeric_limits<float>::infinity()
                       : i % 11 == 0 ? std::numeric_limits<float>::quiet_NaN()
                                     : 1.0f;
    g.before.depth[i] = i % 13 == 0 ? std::numeric_limits<float>::infinity() : g.after.depth[i];
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
    const glm::vec3 emission = i % 3 == 0   ? glm::vec3(0.0f)
                               : i % 3 == 1 ? glm::vec3(next() % 1000, next() % 7, 650.0f) * 0.01f
                                            : glm::vec3(65408.0f, 0.5f, next() % 65408);  // RGB9E5's largest
    g.after.emissive[i] = g.before.emissive[i] = {pack_rgb9e5(emission)};
    g.after.occlusion[i] = g.before.occlusion[i] = static_cast<std::uint8_t>(r >> 16);
  }
  return g;
}

TEST(LightingLanes, ExtremeGBuffersLightToTheReferencesBits) {
  const int width = 61, height = 53;  // 61: seven full lanes and five in each row
  const GBuffers g = extreme_gbuffers(width, height);
  Camera camera = frame_camera(Bounds{glm::dvec3(-1), glm::dvec3(1)}, 10, 80, 120, static_cast<double>(width) / height);
  const Environment furnace = uniform_environment(glm::vec3(1.0f));      // no sun, one radiance everywhere
  const Environment blinding = uniform_environment(glm::vec3(3.0e38f));  // sums overflow to infinity
  for (const auto& [name, options] : option_sets()) {
    expect_identical_passes(g, default_environment(), camera, options, name);
    expect_identical_passes(g, furnace, camera, options, name + ", furnace");
    expect_identical_passes(g, blinding, camera, options, name + ", blinding");
  }
  camera.orthographic = true;  // every ray the same
  expect_identical_passes(g, default_environment(), camera, LightingOptions{}, "orthographic");
}

// Rows shorter than one group of lanes, and one row alone: lanes past its end are never stored
// (the sanitizer build would see a write past the image).
TEST(LightingLanes, RowsShorterThanEightPixelsStoreOnlyTheirOwn) {
  for (const auto& [width, height] : {std::pair{1, 1}, std::pair{5, 1}, std::pair{7, 3}, std::pair{9, 1}}) {
    const GBuffers g = extreme_gbuffers(width, height);
    const Camera camera = frame_camera(Bounds{glm::dvec3(-1), glm::dvec3(1)}, 30, 10, 60, 1.0);
    expect_identical_passes(g, default_environment(), camera, LightingOptions{},
                            std::to_string(width) + " x " + std::to_string(height));
  }
}

}  // namespace
}  // namespace gltf_pbr::preview
