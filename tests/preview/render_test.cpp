// The whole pipeline: analytic spheres against closed forms, conversions that are exact, Draco
// meshes, and the real assets of ../shared (read in place, never copied).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "converter/legacy_material.hpp"
#include "converter/solver.hpp"
#include "core/asset.hpp"
#include "core/color.hpp"
#include "core/error.hpp"
#include "preview/gbuffer.hpp"
#include "preview/preview.hpp"

namespace gltf_pbr::preview {
namespace {

fs::path assets_dir() { return fs::path(GLTF_PBR_SHARED_DIR) / "assets"; }

// A UV sphere of radius 1 with normals, indexed (uint16), and one spec-gloss material.
Asset sphere_asset(glm::vec4 diffuse, glm::vec3 specular, float glossiness) {
  std::vector<float> positions, normals;
  std::vector<std::uint16_t> indices;
  const int rings = 32, segments = 64;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const float theta = 3.14159265f * r / rings, phi = 2.0f * 3.14159265f * s / segments;
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      for (int k = 0; k < 3; ++k) positions.push_back(n[k]), normals.push_back(n[k]);
    }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const auto a = static_cast<std::uint16_t>(r * (segments + 1) + s),
                 b = static_cast<std::uint16_t>(a + segments + 1);
      for (std::uint16_t i : {a, static_cast<std::uint16_t>(a + 1), b, b, static_cast<std::uint16_t>(a + 1),
                              static_cast<std::uint16_t>(b + 1)})
        indices.push_back(i);
    }
  Asset asset;
  asset.path = "sphere.gltf";
  tinygltf::Model& m = asset.model;
  tinygltf::Buffer buffer;
  auto append = [&](const void* data, size_t bytes) {
    const size_t offset = buffer.data.size();
    buffer.data.resize(offset + bytes);
    std::memcpy(buffer.data.data() + offset, data, bytes);
    return offset;
  };
  auto view_and_accessor = [&](size_t offset, size_t bytes, int component, int type, size_t count) {
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = bytes;
    m.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = static_cast<int>(m.bufferViews.size() - 1);
    accessor.componentType = component;
    accessor.type = type;
    accessor.count = count;
    m.accessors.push_back(accessor);
    return static_cast<int>(m.accessors.size() - 1);
  };
  const size_t p = append(positions.data(), positions.size() * 4);
  const size_t n = append(normals.data(), normals.size() * 4);
  const size_t i = append(indices.data(), indices.size() * 2);
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = view_and_accessor(p, positions.size() * 4, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                       TINYGLTF_TYPE_VEC3, positions.size() / 3);
  primitive.attributes["NORMAL"] =
      view_and_accessor(n, normals.size() * 4, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, normals.size() / 3);
  primitive.indices = view_and_accessor(i, indices.size() * 2, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                        TINYGLTF_TYPE_SCALAR, indices.size());
  primitive.material = 0;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  m.buffers.push_back(buffer);
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(primitive);
  m.meshes.push_back(mesh);
  tinygltf::Material material;
  material.name = "legacy";
  auto array = [](std::initializer_list<double> values) {
    tinygltf::Value::Array a;
    for (double v : values) a.emplace_back(v);
    return tinygltf::Value(a);
  };
  tinygltf::Value::Object extension;
  extension["diffuseFactor"] = array({diffuse.x, diffuse.y, diffuse.z, diffuse.w});
  extension["specularFactor"] = array({specular.x, specular.y, specular.z});
  extension["glossinessFactor"] = tinygltf::Value(static_cast<double>(glossiness));
  material.extensions[kSpecGloss] = tinygltf::Value(extension);
  m.materials.push_back(material);
  m.extensionsUsed.push_back(kSpecGloss);
  tinygltf::Node node;
  node.mesh = 0;
  node.scale = {2.0, 2.0, 2.0};  // under a node transform
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  m.asset.version = "2.0";
  return asset;
}

PreviewOptions small(int size) {
  PreviewOptions options;
  options.width = options.height = size;
  return options;
}

TEST(GBuffer, UnitNormalsPackWithinAStepAndOnesWithNoDirectionAsPlusZ) {
  for (const glm::vec3 n : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::normalize(glm::vec3(1, -2, 3)),
                            glm::normalize(glm::vec3(-3, 1, -0.5f)), glm::vec3(1, 0, 0)})
    EXPECT_GT(glm::dot(unpack_octahedral_12_12(pack_octahedral_12_12(n)), n), 0.9999f);
  // A skin scaled past float's range gives normals of infinity or NaN; a degenerate triangle, zero.
  for (const glm::vec3 n :
       {glm::vec3(0.0f), glm::vec3(NAN, 0, 1), glm::vec3(INFINITY, -INFINITY, 0), glm::vec3(INFINITY, 0, 0)})
    EXPECT_EQ(pack_octahedral_12_12(n), pack_octahedral_12_12(glm::vec3(0, 0, 1)));
}

TEST(Render, MetalThatConvertsExactlyLooksTheSameBeforeAndAfter) {
  // Black diffuse + copper F0 is a metal in both models: m = 1, base = F0, roughness = 1 - g.
  const Asset asset = sphere_asset(glm::vec4(0, 0, 0, 1), glm::vec3(0.955f, 0.638f, 0.538f), 0.6f);
  const PreviewResult r = render_preview(asset, small(160));
  EXPECT_GT(r.metrics.pixels_compared, 160 * 160 / 5);
  EXPECT_LT(r.metrics.delta_e_mean, 0.3);
  EXPECT_LT(r.metrics.delta_e_p95, 0.8);
  EXPECT_LT(r.metrics.rms_db, -40.0);
}

TEST(Render, AGltfCameraWithNoFieldOfViewIsBadInputNamingIt) {
  Asset asset = sphere_asset(glm::vec4(0.5f, 0.5f, 0.5f, 1), glm::vec3(0.04f), 0.5f);
  tinygltf::Camera camera;
  camera.type = "perspective";
  camera.perspective.yfov = 0.0;
  camera.perspective.znear = 0.1;
  asset.model.cameras.push_back(camera);
  tinygltf::Node viewer;
  viewer.camera = 0;
  viewer.translation = {0.0, 0.0, 10.0};
  asset.model.nodes.push_back(viewer);
  asset.model.scenes[0].nodes.push_back(1);
  PreviewOptions options = small(32);
  options.gltf_camera = 0;
  try {
    (void)render_preview(asset, options);
    FAIL() << "drew through a camera of yfov 0";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer, "/cameras/0/perspective");
    EXPECT_NE(e.reason.find("yfov"), std::string::npos) << e.reason;
  }
  asset.model.cameras[0].perspective.yfov = 0.8;  // the same view through a real field of view draws
  EXPECT_GT(render_preview(asset, options).metrics.pixels_compared, 0);
}

// Grey dielectric spheres (specular other than 0.04 over diffuse colours, three glossinesses),
// drawn before and after each model's solve under the built-in sky and sun: the mean ΔE2000 over
// each sphere. A 0.04 specular converts exactly and previews without a difference under both
// (0.2 ΔE2000 from the G-buffer's 8-bit specular). For
// the others the appearance model keeps the look closer than the normal-incidence one on average
// at every specular level (measured on 96 px spheres; the test draws 64 px ones: 0 -> 1.33 against 1.98, 0.02 -> 0.71 /
// 0.99, 0.1 -> 1.28 / 1.87, 0.2 -> 2.48 / 3.80), but not within 1 ΔE2000 on every sphere: its worst are 3.0 at specular
// 0 and 6.5 at 0.2 (dark glossy and saturated red spheres). At 0 and 0.02 that is the floor a core material reaches
// under this sky (3.0 and 1.2 by a search over base and metalness): the F0 of at least 0.04 mirrors the sky's sun,
// horizon and ground where the legacy mirrored little, which no uniform base can follow (under a uniform environment
// the same search reaches 0.01). At 0.1 and 0.2 the model keeps the normal-incidence metalness and weighs the
// normal-incidence fit at half, for continuity and for real assets: an appearance-only fit drew these spheres closer
// (0.2 -> 1.70, worst 4.5) but real assets farther (bench/RESULTS.md, sessions 34 and 41).
TEST(Render, GreyDielectricSpheresLookCloserUnderTheAppearanceModel) {
  const glm::vec3 diffuses[] = {glm::vec3(0.05f),     glm::vec3(0.2f),    glm::vec3(0.5f),    glm::vec3(0.8f),
                                {0.8f, 0.05f, 0.05f}, {0.8f, 0.6f, 0.1f}, {0.1f, 0.25f, 0.7f}};
  const auto sphere_delta_e = [&](const SpecGloss& legacy, ErrorModel model) {
    const SpherePair sphere{legacy, solve(legacy, solver_preset(SolverEffort::Balanced, model))};
    Camera camera;
    const PreviewOptions options = small(64);
    return light_and_compare(sphere_gbuffers(std::span(&sphere, 1), 1, 64, &camera), camera, default_environment(),
                             options)
        .metrics.delta_e_mean;
  };
  for (const float specular : {0.0f, 0.02f, 0.04f, 0.1f, 0.2f}) {
    double normal_incidence = 0, appearance = 0;
    for (const glm::vec3 diffuse : diffuses)
      for (const float glossiness : {0.2f, 0.5f, 0.8f}) {
        const SpecGloss legacy{diffuse, glm::vec3(specular), glossiness};
        const double ni = sphere_delta_e(legacy, ErrorModel::NormalIncidence);
        const double seen = sphere_delta_e(legacy, ErrorModel::Appearance);
        if (specular == kDielectricF0) {
          EXPECT_LT(ni, 0.3) << diffuse.r << " " << glossiness;  // the G-buffer keeps specular in 8-bit sRGB: 0.0395
          EXPECT_LT(seen, 0.3) << diffuse.r << " " << glossiness;
        }
        EXPECT_LT(seen, 7.0) << specular << " " << diffuse.r << "," << diffuse.g << " " << glossiness;
        normal_incidence += ni, appearance += seen;
      }
    if (specular != kDielectricF0) {
      EXPECT_LT(appearance, normal_incidence * 0.75) << specular;
      EXPECT_LT(appearance / 21.0, specular == 0.2f ? 2.75 : 1.5) << specular;
    }
  }
}

// Real assets whose legacy sheen is a grey far from 0.04 (Box and BoxTextured 0.2 over a red
// diffuse or a logo, RiggedSimple 0.5): the appearance model draws them closer to the original
// than the normal-incidence one (measured at the test's 128²: Box 1.70 against 3.10 ΔE2000 mean,
// BoxTextured 0.97 / 1.32, RiggedSimple 4.36 / 7.45; bench/RESULTS.md, session 41).
TEST(Render, AssetsWithAGreySheenLookCloserUnderTheAppearanceModel) {
  for (const char* relative : {"Box/specgloss/Box.gltf", "BoxTextured/specgloss/BoxTextured.gltf",
                               "RiggedSimple/specgloss/RiggedSimple.gltf"}) {
    const Asset asset = load_asset(assets_dir() / relative);
    PreviewOptions options = small(128);
    options.convert.solver = solver_preset(SolverEffort::Balanced, ErrorModel::NormalIncidence);
    const double normal_incidence = render_preview(asset, options).metrics.delta_e_mean;
    options.convert.solver = solver_preset(SolverEffort::Balanced, ErrorModel::Appearance);
    const double appearance = render_preview(asset, options).metrics.delta_e_mean;
    EXPECT_LT(appearance, 0.8 * normal_incidence) << relative;
  }
}

// The appearance model's known loss: VC's glossy specular-0 surfaces gain a mirror image of the
// built-in sky from core's F0 0.04, which is blue, and the model, taking the sky for grey, darkens
// the base by grey (measured at 128²: 1.78 against 1.26 ΔE2000 mean; under a uniform white
// environment they tie: the next test). The loss must not grow.
TEST(Render, GlossySpecularZeroAssetLooksOnlyALittleFartherUnderTheAppearanceModel) {
  const Asset asset = load_asset(assets_dir() / "VC/specgloss/VC.gltf");
  PreviewOptions options = small(128);
  options.convert.solver = solver_preset(SolverEffort::Balanced, ErrorModel::NormalIncidence);
  const double normal_incidence = render_preview(asset, options).metrics.delta_e_mean;
  options.convert.solver = solver_preset(SolverEffort::Balanced, ErrorModel::Appearance);
  const double appearance = render_preview(asset, options).metrics.delta_e_mean;
  EXPECT_LT(appearance, 1.6 * normal_incidence);
}

// Under a uniform white environment without a sun every direction mirrors the same grey, which
// the model assumes of the sky's average (though it takes the diffuse light for 1.94 times the
// mirrored radiance, where here they are equal): the appearance model draws the sheened assets
// closer than normal incidence here too, and VC, its loss under the built-in sky's blue, alike
// (within 1%). Duck sits at the gamut's edge (most of its reds are 254-255, leaving no room for
// base = diffuse / 0.96) and is drawn 2% farther. Measured at the test's 128², ΔE2000 mean,
// appearance against normal incidence: Avocado 0.55 / 0.77, Box 11.69 / 14.86, BoxTextured 3.11 /
// 4.75, CesiumMan 0.74 / 1.05, RiggedSimple 5.13 / 9.09, VC 1.392 / 1.398, Duck 0.422 / 0.413.
TEST(Render, UnderANeutralEnvironmentTheAppearanceModelDrawsSheenedAssetsCloserAndVCAlike) {
  const struct {
    const char* relative;
    double bound;  // on appearance / normal incidence
  } cases[] = {{"Avocado/specgloss/Avocado.gltf", 0.85},
               {"Box/specgloss/Box.gltf", 0.85},
               {"BoxTextured/specgloss/BoxTextured.gltf", 0.85},
               {"CesiumMan/specgloss/CesiumMan.gltf", 0.85},
               {"RiggedSimple/specgloss/RiggedSimple.gltf", 0.85},
               {"VC/specgloss/VC.gltf", 1.01},
               {"Duck/specgloss/Duck.gltf", 1.04}};
  PreviewOptions options = small(128);
  options.environment = "neutral";  // a name only: the loaded environment is used
  options.loaded_environment = std::make_shared<const Environment>(uniform_environment(glm::vec3(1.0f)));
  for (const auto& [relative, bound] : cases) {
    const Asset asset = load_asset(assets_dir() / relative);
    options.convert.solver = solver_preset(SolverEffort::Balanced, ErrorModel::NormalIncidence);
    const double normal_incidence = render_preview(asset, options).metrics.delta_e_mean;
    options.convert.solver = solver_preset(SolverEffort::Balanced, ErrorModel::Appearance);
    const double appearance = render_preview(asset, options).metrics.delta_e_mean;
    EXPECT_LT(appearance, bound * normal_incidence)
        << relative << ": " << appearance << " against " << normal_incidence;
  }
}

TEST(Render, FactorOnlySceneHasNoEmissiveOrOcclusionBuffer) {
  const Asset asset = sphere_asset(glm::vec4(0.5f, 0.2f, 0.1f, 1), glm::vec3(0.04f), 0.5f);
  const PreviewResult r = render_preview(asset, small(64));
  int after = 0, before = 0;
  for (const auto& b : r.after_layout) after += b.bytes_per_pixel;
  for (const auto& b : r.before_layout) before += b.bytes_per_pixel;
  EXPECT_EQ(after, 12);   // depth 4 + normal/roughness 4 + albedo/metalness 4
  EXPECT_EQ(before, 14);  // depth 4 + normal/gloss 4 + diffuse/specular 6
  EXPECT_EQ(r.scene.textures_decoded, 0);
}

TEST(Render, LambertSphereMatchesClosedFormAndIsSymmetric) {
  // Sun behind the (orthographic) camera, black environment, diffuse 0.5, specular 0: the legacy
  // model reduces to Lambert, L = (0.5 / pi) E (n.l), and F = 0 exactly because H = V.
  GridOptions grid;
  grid.rows = grid.columns = 1;
  grid.cell = 128;
  Camera camera;
  GBuffers g = sphere_grid_gbuffers(grid, &camera);
  const std::uint8_t half_srgb = 188;  // sRGB code of linear ~0.5
  const float diffuse = std::pow((half_srgb / 255.0f + 0.055f) / 1.055f, 2.4f);
  for (auto& d : g.before.diffspec) d = {{half_srgb, half_srgb, half_srgb}, {0, 0, 0}};
  Environment env = uniform_environment(glm::vec3(0.0f));
  env.sun_direction = glm::vec3(0, 0, 1);
  env.sun_irradiance = glm::vec3(3.0f);
  const HdrImage image = light_both(g, env, camera, LightingOptions{}, /*keep_radiance=*/true).before_hdr;
  int checked = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      const size_t i = static_cast<size_t>(y * 128 + x);
      if (!image.covered[i]) continue;
      const float lx = (x + 0.5f - 64.0f) / (0.42f * 128), ly = (y + 0.5f - 64.0f) / (0.42f * 128);
      const float n_dot_l = std::sqrt(std::max(0.0f, 1.0f - lx * lx - ly * ly));
      const float expected = diffuse / kPi * 3.0f * n_dot_l;
      ASSERT_NEAR(image.radiance[i].x, expected, 0.004f + 0.01f * expected) << x << "," << y;
      const size_t mirror_x = static_cast<size_t>(y * 128 + (127 - x)),
                   mirror_y = static_cast<size_t>((127 - y) * 128 + x);
      ASSERT_NEAR(image.radiance[i].x, image.radiance[mirror_x].x, 0.004f);
      ASSERT_NEAR(image.radiance[i].x, image.radiance[mirror_y].x, 0.004f);
      ++checked;
    }
  EXPECT_GT(checked, 8000);
}

TEST(Render, GridMetalRowIsIdenticalOnBothSides) {
  // to_spec_gloss of a pure metal is exact (black diffuse, specular = albedo): the bottom row of
  // the metalness x roughness array must not differ, whatever the roughness.
  GridOptions grid;
  grid.albedo = glm::vec3(0.95f, 0.64f, 0.54f);
  grid.rows = grid.columns = 5;
  grid.cell = 40;
  const PreviewResult r = render_grid(grid, PreviewOptions{});
  double sum = 0;
  long count = 0;
  for (int y = 4 * 40; y < 5 * 40; ++y)
    for (int x = 0; x < 200; ++x) {
      const size_t i = static_cast<size_t>(y * 200 + x);
      if (!r.covered[i]) continue;
      for (int k = 0; k < 3; ++k)
        sum += std::abs(r.before[i * 3 + static_cast<size_t>(k)] - r.after[i * 3 + static_cast<size_t>(k)]);
      ++count;
    }
  ASSERT_GT(count, 1000);
  EXPECT_LT(sum / count / 3, 0.6);  // under one 8-bit level on average
}

TEST(Render, SphereGridHasNoFireflies) {
  // Roughness 0 to 1, metalness 0 to 1, grazing rims included, lit by the environment (the sun's
  // mirror highlight is a true Dirac peak, so it is off here): no pixel may outshine the median
  // of its 3 x 3 neighbourhood by more than 3x, and none is NaN or Inf.
  GridOptions grid;
  grid.albedo = glm::vec3(1.0f);
  grid.rows = grid.columns = 6;
  grid.cell = 48;
  PreviewOptions options;
  options.lighting.sun = false;
  options.keep_radiance = true;
  const PreviewResult r = render_grid(grid, options);
  const int w = r.width, h = r.height;
  auto luminance = [&](const HdrImage& image, int x, int y) {
    const glm::vec3 c = image.radiance[static_cast<size_t>(y * w + x)];
    return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
  };
  for (const HdrImage* image : {&r.before_hdr, &r.after_hdr})
    for (int y = 1; y < h - 1; ++y)
      for (int x = 1; x < w - 1; ++x) {
        const float centre = luminance(*image, x, y);
        ASSERT_TRUE(std::isfinite(centre));
        float around[9];
        int k = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) around[k++] = luminance(*image, x + dx, y + dy);
        std::nth_element(around, around + 4, around + 9);
        ASSERT_LE(centre, 3.0f * around[4] + 0.05f) << x << "," << y;
      }
}

TEST(Render, LightingTonemapsInItsOwnPassAsToSrgb8DoesAndKeepsRadianceOnlyWhenAsked) {
  GridOptions grid;
  grid.rows = grid.columns = 3;
  grid.cell = 32;
  PreviewOptions options;
  const PreviewResult lean = render_grid(grid, options);
  EXPECT_TRUE(lean.before_hdr.radiance.empty());
  EXPECT_TRUE(lean.after_hdr.radiance.empty());
  options.keep_radiance = true;
  const PreviewResult kept = render_grid(grid, options);
  EXPECT_EQ(kept.after, to_srgb8(kept.after_hdr, options.lighting));
  EXPECT_EQ(kept.before, to_srgb8(kept.before_hdr, options.lighting));
  EXPECT_EQ(lean.after, kept.after);
  EXPECT_EQ(lean.before, kept.before);
  EXPECT_EQ(lean.covered, kept.covered);
}

TEST(Render, Srgb8EncodingGivesEveryStepTheCodeWhoseIntervalHoldsIt) {
  // The definition, directly: a linear value quantised to step i of 65535 encodes as the number of
  // codes k whose interval starts at or below it, (k - 0.5) / 255 in sRGB (IEC 61966-2-1).
  std::vector<float> first_step;
  for (int k = 1; k < 256; ++k) first_step.push_back(srgb_to_linear((k - 0.5f) / 255.0f) * 65535.0f);
  for (int i = 0; i < 65536; ++i) {
    const auto expected = std::count_if(first_step.begin(), first_step.end(),
                                        [&](float first) { return static_cast<float>(i) >= first; });
    ASSERT_EQ(encode_srgb8(static_cast<float>(i) / 65535.0f), expected) << "step " << i;
  }
  EXPECT_EQ(encode_srgb8(-1.0f), 0);
  EXPECT_EQ(encode_srgb8(std::nanf("")), 0);
  EXPECT_EQ(encode_srgb8(2.0f), 255);
  EXPECT_EQ(encode_srgb8(std::numeric_limits<float>::infinity()), 255);
}

TEST(Render, DracoMeshDrawsLikeItsUncompressedOriginal) {
  const fs::path plain = assets_dir() / "2CylinderEngine/specgloss/2CylinderEngine.gltf";
  const fs::path draco_folder = assets_dir() / "2CylinderEngine/specgloss-draco-generated";
  ASSERT_TRUE(fs::is_directory(draco_folder)) << draco_folder;  // ../shared must be there: CI puts it beside us
  fs::path draco;
  for (const auto& e : fs::directory_iterator(draco_folder))
    if (e.path().extension() == ".gltf" || e.path().extension() == ".glb") draco = e.path();
  ASSERT_FALSE(draco.empty());
  const PreviewResult a = render_preview(load_asset(plain), small(192));
  const PreviewResult b = render_preview(load_asset(draco), small(192));
  EXPECT_EQ(a.scene.draco_primitives, 0);
  EXPECT_GT(b.scene.draco_primitives, 0);
  const DifferenceMetrics m = compare_images(a.after, b.after, a.covered, 192, 192);
  EXPECT_LT(m.delta_e_mean, 1.5);
  long differing = 0;
  for (size_t i = 0; i < a.covered.size(); ++i) differing += a.covered[i] != b.covered[i];
  EXPECT_LT(differing, 192 * 192 / 100);
}

// Decode nothing twice: the preview's scene takes the pixels its conversion decoded (the spec-gloss
// inputs) and baked (the PNG outputs, and the decode of each JPEG base colour, which the
// conversion measures as written), and draws exactly what decoding them again would draw.
TEST(Render, ThePreviewDecodesNoImageItsConversionHeldAndDrawsTheSame) {
  for (const char* file : {"Avocado/specgloss/Avocado.gltf", "VC/specgloss/VC.gltf"}) {
    const fs::path path = assets_dir() / file;
    ASSERT_TRUE(fs::exists(path)) << path;
    const Asset asset = load_asset(path);
    const long decoded_before = work_counters().images_decoded.load();
    const PreviewResult handed_over = render_preview(asset, small(128));
    const long decoded = work_counters().images_decoded.load() - decoded_before;
    EXPECT_EQ(decoded, handed_over.conversion->images_decoded + handed_over.scene.textures_decoded) << file;
    EXPECT_GT(handed_over.scene.textures_from_conversion, 0) << file;

    Asset converted = asset;
    (void)convert(converted, PreviewOptions{}.convert);
    const PreviewResult decoded_again = render_pair(asset, converted, small(128));
    EXPECT_EQ(decoded_again.scene.textures_from_conversion, 0) << file;
    EXPECT_EQ(decoded_again.scene.textures_decoded,
              handed_over.scene.textures_decoded + handed_over.scene.textures_from_conversion)
        << file;
    EXPECT_EQ(handed_over.before, decoded_again.before) << file;
    EXPECT_EQ(handed_over.after, decoded_again.after) << file;
  }
  // Avocado: diffuse and specular-glossiness (decoded by the conversion), base colour and
  // metallic-roughness (baked as PNG) handed over; only the normal map is the scene's to decode.
  const PreviewResult avocado = render_preview(load_asset(assets_dir() / "Avocado/specgloss/Avocado.gltf"), small(64));
  EXPECT_EQ(avocado.scene.textures_from_conversion, 4);
  EXPECT_EQ(avocado.scene.textures_decoded, 1);
}

// Every texel of both G-buffers equal (depth aside: the same raster gives it).
void expect_same_gbuffers(const GBuffers& a, const GBuffers& b, const std::string& label) {
  ASSERT_EQ(a.after.normal.size(), b.after.normal.size()) << label;
  EXPECT_TRUE(a.after.occlusion == b.after.occlusion && a.before.occlusion == b.before.occlusion) << label;
  ASSERT_EQ(a.after.emissive.size(), b.after.emissive.size()) << label;
  for (size_t i = 0; i < a.after.emissive.size(); ++i)
    ASSERT_EQ(a.after.emissive[i].rgb9e5, b.after.emissive[i].rgb9e5) << label << " pixel " << i;
  for (size_t i = 0; i < a.after.normal.size(); ++i) {
    ASSERT_EQ(a.after.normal[i].bits, b.after.normal[i].bits) << label << " pixel " << i;
    ASSERT_EQ(a.before.normal[i].bits, b.before.normal[i].bits) << label << " pixel " << i;
    ASSERT_EQ(std::memcmp(&a.after.albedo[i], &b.after.albedo[i], sizeof(AlbedoMetalness)), 0) << label << i;
    ASSERT_EQ(std::memcmp(&a.before.diffspec[i], &b.before.diffspec[i], sizeof(DiffuseSpecular)), 0) << label << i;
  }
}

// Decode nothing a step does not use: a render keeps of each texture only the mip levels its
// pixels sample (and decodes no image none of them samples), and draws exactly what every level draws.
TEST(Render, TexturesKeepOnlyTheLevelsTheirPixelsSampleAndDrawTheSame) {
  for (const char* file : {"Avocado/specgloss/Avocado.gltf", "VC/specgloss/VC.gltf"}) {
    const Asset asset = load_asset(assets_dir() / file);
    Asset converted = asset;
    (void)convert(converted, PreviewOptions{}.convert);
    const Scene every_level = build_scene(asset, converted);
    Scene sampled = build_scene(asset, converted, nullptr, TextureLoading::SampledLevelsLater);
    ASSERT_TRUE(sampled.unloaded) << file;
    ASSERT_EQ(sampled.textures.size(), every_level.textures.size()) << file;
    for (const auto& texture : sampled.textures) EXPECT_TRUE(texture->rgba.empty()) << file;  // no masked materials
    const Camera camera = frame_camera(every_level.bounds, 35, 20, 40, 1.0);
    const VisibilityBuffer visibility = rasterize(sampled, camera, 128, 128);
    const std::vector<int> first_levels = finest_sampled_levels(sampled, visibility, camera);
    load_textures(sampled, first_levels);
    EXPECT_FALSE(sampled.unloaded);

    size_t kept = 0, every = 0, coarser = 0, unsampled = 0;
    for (size_t i = 0; i < sampled.textures.size(); ++i) {
      const Texture& t = *sampled.textures[i];
      if (first_levels[i] == kUnsampled) {
        ++unsampled;
        EXPECT_TRUE(t.rgba.empty() &&
                    std::all_of(t.mips.begin(), t.mips.end(), [](const TextureLevel& l) { return l.rgba.empty(); }));
        continue;
      }
      EXPECT_EQ(t.first_level, std::min<int>(first_levels[i], static_cast<int>(t.mips.size()))) << file;
      coarser += t.first_level > 0;
      EXPECT_EQ(t.rgba.empty(), t.first_level > 0);
      for (size_t level = 1; level <= t.mips.size(); ++level)
        EXPECT_EQ(t.mips[level - 1].rgba.empty(), static_cast<int>(level) < t.first_level)
            << file << " level " << level;
      kept += t.rgba.size();
      for (const auto& level : t.mips) kept += level.rgba.size();
    }
    for (const auto& t : every_level.textures) {
      every += t->rgba.size();
      for (const auto& level : t->mips) every += level.rgba.size();
    }
    EXPECT_GT(coarser, 0u) << file;
    EXPECT_LT(kept * 4, every) << file;  // 128 pixels across: most of each chain is left out
    if (std::string(file).find("VC") != std::string::npos) {
      EXPECT_GT(unsampled, 0u);  // parts out of view
    }

    expect_same_gbuffers(fill_gbuffers(every_level, rasterize(every_level, camera, 128, 128), camera),
                         fill_gbuffers(sampled, visibility, camera), file);
  }
}

// The rasterizer tests the alpha of masked materials at level 0, so their base colour is made at
// once; what the raster and the resolve then draw equals what they draw with every level.
TEST(Render, AMaskedMaterialsBaseColourIsMadeBeforeTheRaster) {
  Asset asset = load_asset(assets_dir() / "BoxTextured/specgloss/BoxTextured.gltf");
  for (auto& material : asset.model.materials) material.alphaMode = "MASK";
  Asset converted = asset;
  (void)convert(converted, PreviewOptions{}.convert);
  const Scene every_level = build_scene(asset, converted);
  Scene sampled = build_scene(asset, converted, nullptr, TextureLoading::SampledLevelsLater);
  const Texture* base = sampled.materials[0].base_color_texture.texture;
  ASSERT_NE(base, nullptr);
  EXPECT_FALSE(base->rgba.empty());
  EXPECT_EQ(base->first_level, 0);
  ASSERT_TRUE(sampled.unloaded);  // the legacy side's textures wait
  const Camera camera = frame_camera(every_level.bounds, 35, 20, 40, 1.0);
  const VisibilityBuffer visibility = rasterize(sampled, camera, 96, 96);
  load_textures(sampled, finest_sampled_levels(sampled, visibility, camera));
  const VisibilityBuffer every_visibility = rasterize(every_level, camera, 96, 96);
  long covered = 0;
  for (size_t i = 0; i < visibility.samples.size(); ++i) {
    ASSERT_EQ(visibility.samples[i].empty(), every_visibility.samples[i].empty()) << "pixel " << i;
    covered += !visibility.samples[i].empty();
  }
  EXPECT_GT(covered, 96 * 96 / 20);
  expect_same_gbuffers(fill_gbuffers(every_level, every_visibility, camera), fill_gbuffers(sampled, visibility, camera),
                       "masked BoxTextured");
}

TEST(Render, EverySharedAssetDrawsFiniteAndFramed) {
  const char* files[] = {"Box/specgloss/Box.gltf",
                         "BoxInterleaved/specgloss/BoxInterleaved.gltf",
                         "BoxTextured/specgloss/BoxTextured.gltf",
                         "BoxTexturedNonPowerOfTwo/specgloss/BoxTexturedNonPowerOfTwo.gltf",
                         "Duck/specgloss/Duck.gltf",
                         "RiggedSimple/specgloss/RiggedSimple.gltf",
                         "CesiumMan/specgloss/CesiumMan.gltf",
                         "CesiumMilkTruck/specgloss/CesiumMilkTruck.gltf",
                         "VC/specgloss/VC.gltf"};
  for (const char* file : files) {
    const fs::path path = assets_dir() / file;
    if (!fs::exists(path)) {
      ADD_FAILURE() << "missing " << path;
      continue;
    }
    PreviewOptions options = small(96);
    options.keep_radiance = true;
    const PreviewResult r = render_preview(load_asset(path), options);
    ASSERT_EQ(r.after_hdr.radiance.size(), 96u * 96u) << file;
    long covered = 0;
    for (auto c : r.covered) covered += c;
    EXPECT_GT(covered, 96 * 96 / 20) << file;
    for (const auto& c : r.after_hdr.radiance) ASSERT_TRUE(std::isfinite(c.x + c.y + c.z)) << file;
    for (const auto& c : r.before_hdr.radiance) ASSERT_TRUE(std::isfinite(c.x + c.y + c.z)) << file;
    // Automatic framing keeps the image border clear (the bounding sphere fits the view).
    long border = 0;
    for (int k = 0; k < 96; ++k)
      border += r.covered[static_cast<size_t>(k)] + r.covered[static_cast<size_t>(95 * 96 + k)] +
                r.covered[static_cast<size_t>(k * 96)] + r.covered[static_cast<size_t>(k * 96 + 95)];
    EXPECT_EQ(border, 0) << file;
  }
}

}  // namespace
}  // namespace gltf_pbr::preview
