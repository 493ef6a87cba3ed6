// Material plausibility (PBR_*): the real 2CylinderEngine CAD materials, every measured metal and
// the dielectric classes of DESIGN.md, texel coverage and heat maps, conversions of every shared
// asset, and user config overrides.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "converter/convert.hpp"
#include "core/image_header.hpp"
#include "core/material_model.hpp"
#include "material_test_support.hpp"
#include "test_support.hpp"
#include "validators/materials/f0_reference.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

using namespace test;  // the builders and report queries of the test support headers

const std::string kLegacy = "/extensions/KHR_materials_pbrSpecularGlossiness";

fs::path two_cylinder_engine() { return test::assets_dir() / "2CylinderEngine/specgloss/2CylinderEngine.gltf"; }

// Codes reported at each pointer.
std::map<std::string, std::set<std::string>> codes_by_pointer(const Report& report) {
  std::map<std::string, std::set<std::string>> codes;
  for (const Issue& issue : report.messages) codes[issue.pointer].insert(issue.code);
  return codes;
}

TEST(MaterialPlausibility, TwoCylinderEngineFlagsSpecular08AndColouredSpecularOnDiffuse085) {
  const Asset asset = load_asset(two_cylinder_engine());
  const Report report = validate_in_memory(asset, builtin_rules(LintProfile::Strict));
  auto codes = codes_by_pointer(report);

  // Material 0: diffuse 0.85 grey, specular 0.8 grey. A metal's F0 over a diffuse surface, and
  // diffuse + specular = 1.65.
  const std::string m0 = "/materials/0" + kLegacy;
  EXPECT_TRUE(codes[m0 + "/diffuseFactor"].contains("PBR_METAL_WITH_DIFFUSE"));
  EXPECT_TRUE(codes[m0 + "/specularFactor"].contains("PBR_ENERGY_NOT_CONSERVED"));
  EXPECT_FALSE(codes[m0 + "/specularFactor"].contains("PBR_METAL_F0_TOO_DARK"));  // 0.8 is bright enough
  EXPECT_TRUE(codes[m0 + "/glossinessFactor"].contains("PBR_ROUGHNESS_ZERO"));
  EXPECT_TRUE(codes[m0].contains("PBR_LEGACY_SPEC_GLOSS"));

  // Material 2: diffuse (0.85, 0.561, 0), coloured specular (0.8, 0.528, 0): also too dark for a
  // metal in the strict profile (mean 0.443 < 0.45), and named after the metal it resembles.
  const std::string m2 = "/materials/2" + kLegacy;
  EXPECT_TRUE(codes[m2 + "/diffuseFactor"].contains("PBR_METAL_WITH_DIFFUSE"));
  EXPECT_TRUE(codes[m2 + "/specularFactor"].contains("PBR_ENERGY_NOT_CONSERVED"));
  EXPECT_TRUE(codes[m2 + "/specularFactor"].contains("PBR_METAL_F0_TOO_DARK"));

  // Material 30: specular 0.6 on diffuse 0.85.
  const std::string m30 = "/materials/30" + kLegacy;
  EXPECT_TRUE(codes[m30 + "/diffuseFactor"].contains("PBR_METAL_WITH_DIFFUSE"));
  EXPECT_TRUE(codes[m30 + "/specularFactor"].contains("PBR_ENERGY_NOT_CONSERVED"));

  // Material 1: black diffuse, specular 0: a dielectric that reflects nothing.
  const std::string m1 = "/materials/1" + kLegacy;
  EXPECT_TRUE(codes[m1 + "/specularFactor"].contains("PBR_DIELECTRIC_F0_TOO_LOW"));
  EXPECT_TRUE(codes[m1 + "/diffuseFactor"].contains("PBR_ALBEDO_TOO_DARK"));
  EXPECT_FALSE(codes[m1 + "/diffuseFactor"].contains("PBR_METAL_WITH_DIFFUSE"));

  // Every material with specular 0.8 in a channel next to diffuse 0.85 breaks energy conservation:
  // exactly those, counted from the file itself.
  int expected_energy = 0;
  for (const auto& material : asset.model.materials) {
    const auto& extension = material.extensions.at("KHR_materials_pbrSpecularGlossiness");
    for (int c = 0; c < 3; ++c)
      if (extension.Get("diffuseFactor").Get(c).GetNumberAsDouble() +
              extension.Get("specularFactor").Get(c).GetNumberAsDouble() >
          1.0) {
        ++expected_energy;
        break;
      }
  }
  EXPECT_EQ(issues_with(report, "PBR_ENERGY_NOT_CONSERVED").size(), static_cast<size_t>(expected_energy));
  EXPECT_GT(expected_energy, 20);

  // Messages name the nearest entry of DESIGN.md's tables.
  for (const Issue& issue : issues_with(report, "PBR_METAL_WITH_DIFFUSE")) {
    if (issue.pointer == m0 + "/diffuseFactor") {
      EXPECT_NE(issue.message.find("F0 0.80 is nearest to Aluminum"), std::string::npos) << issue.message;
    }
  }
  for (const Issue& issue : issues_with(report, "PBR_METAL_F0_TOO_DARK")) {
    if (issue.pointer == m2 + "/specularFactor") {
      EXPECT_NE(issue.message.find("F0 (0.80, 0.53, 0.00) is nearest to Gold"), std::string::npos) << issue.message;
    }
  }
  // The only errors are the two physically impossible ones.
  EXPECT_EQ(report.count(Severity::Error), issues_with(report, "PBR_METAL_WITH_DIFFUSE").size() +
                                               issues_with(report, "PBR_ENERGY_NOT_CONSERVED").size());
}

TEST(MaterialPlausibility, F0IsNamedByTheNearestTableEntry) {
  EXPECT_EQ(describe_f0(glm::vec3(0.972f, 0.960f, 0.915f)), "F0 (0.97, 0.96, 0.92) is Silver");
  EXPECT_EQ(describe_f0(glm::vec3(0.02f)), "F0 0.02 is water");
  EXPECT_EQ(describe_f0(glm::vec3(0.042f)), "F0 0.04 is plastic or glass");
  EXPECT_EQ(nearest_f0_reference(glm::vec3(0.39f)).name, std::string("crystalline silicon (semiconductor)"));
}

TEST(MaterialPlausibility, EveryMeasuredMetalPassesAsThatMetalInBothModels) {
  for (const F0Reference& metal : f0_references()) {
    if (!metal.metal) continue;
    SCOPED_TRACE(metal.name);
    AssetBuilder builder;
    builder.metal_rough(glm::vec4(metal.low, 1.0f), 1.0, 0.3);
    builder.spec_gloss(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), metal.low, 0.7);
    const Report report = validate_in_memory(builder.asset());
    EXPECT_TRUE(problems(report).empty()) << describe(problems(report));
    EXPECT_EQ(nearest_f0_reference(metal.low).name, std::string(metal.name));
    // Gold's red above 1 is information naming gold, in both models.
    const auto above_one = issues_with(report, "PBR_F0_ABOVE_ONE");
    if (std::string(metal.name) == "Gold") {
      ASSERT_EQ(above_one.size(), 2u);
      for (const Issue& issue : above_one) {
        EXPECT_EQ(issue.severity, Severity::Information);
        EXPECT_NE(issue.message.find("is Gold"), std::string::npos) << issue.message;
      }
      EXPECT_EQ(above_one[0].pointer, "/materials/0/pbrMetallicRoughness/baseColorFactor");
      EXPECT_EQ(above_one[1].pointer, "/materials/1" + kLegacy + "/specularFactor");
    } else {
      EXPECT_TRUE(above_one.empty()) << describe(above_one);
    }
  }
}

TEST(MaterialPlausibility, WaterPlasticAndGemsPass) {
  AssetBuilder builder;
  builder.spec_gloss(glm::vec4(0.2f, 0.3f, 0.35f, 1.0f), glm::vec3(0.02f), 0.95);   // water
  builder.spec_gloss(glm::vec4(0.5f, 0.1f, 0.1f, 1.0f), glm::vec3(0.04f), 0.6);     // red plastic
  builder.spec_gloss(glm::vec4(0.1f, 0.1f, 0.3f, 1.0f), glm::vec3(0.07f), 0.9);     // sapphire-like gem
  builder.spec_gloss(glm::vec4(0.05f, 0.05f, 0.05f, 1.0f), glm::vec3(0.17f), 0.9);  // diamond
  builder.metal_rough(glm::vec4(0.5f, 0.5f, 0.5f, 1.0f), 0.0, 0.5);                 // core plastic, F0 0.04
  // Diamond through KHR_materials_ior: ior 2.42, F0 = ((2.42 - 1) / (2.42 + 1))^2 = 0.172.
  tinygltf::Value::Object ior;
  ior["ior"] = tinygltf::Value(2.42);
  builder.metal_rough(glm::vec4(0.05f, 0.05f, 0.05f, 1.0f), 0.0, 0.05).extensions["KHR_materials_ior"] =
      tinygltf::Value(ior);
  // Water through ior 1.33 (F0 0.02).
  ior["ior"] = tinygltf::Value(1.33);
  builder.metal_rough(glm::vec4(0.2f, 0.3f, 0.35f, 1.0f), 0.0, 0.05).extensions["KHR_materials_ior"] =
      tinygltf::Value(ior);
  // Unlit: no reflectance model, so a black base colour is no dark albedo.
  builder.metal_rough(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), 0.0, 0.5).extensions["KHR_materials_unlit"] =
      tinygltf::Value(tinygltf::Value::Object{});
  const Report report = validate_in_memory(builder.asset());
  EXPECT_TRUE(problems(report).empty()) << describe(problems(report));

  const MaterialInputs diamond = read_material_inputs(builder.asset().model, 5);
  const SurfaceSample sample = evaluate_surface(diamond, TexelInputs{});
  EXPECT_NEAR(sample.f0.g, 0.172f, 0.001f);
  EXPECT_EQ(describe_f0(sample.f0), "F0 0.17 is diamond-like gem");
}

TEST(MaterialPlausibility, ImplausibleDielectricsAreFlaggedAtTheirFactor) {
  AssetBuilder builder;
  builder.spec_gloss(glm::vec4(0.5f, 0.5f, 0.5f, 1.0f), glm::vec3(0.2f, 0.1f, 0.05f), 0.5);  // tinted, gem-bright
  builder.metal_rough(glm::vec4(0.98f, 0.98f, 0.98f, 1.0f), 0.0, 0.5);                       // albedo too bright
  builder.metal_rough(glm::vec4(0.5f, 0.5f, 0.5f, 1.0f), 0.5, 0.0);                          // half metal, mirror
  // glTF-Transform's route for a metal: metallic 0, ior 1000, specularColor = the old specular.
  tinygltf::Value::Object specular, ior;
  specular["specularColorFactor"] = test::numbers({0.8, 0.8, 0.8});
  ior["ior"] = tinygltf::Value(1000.0);
  auto& transformed = builder.metal_rough(glm::vec4(0.1f, 0.1f, 0.1f, 1.0f), 0.0, 0.5);
  transformed.extensions["KHR_materials_specular"] = tinygltf::Value(specular);
  transformed.extensions["KHR_materials_ior"] = tinygltf::Value(ior);
  const Report report = validate_in_memory(builder.asset(), builtin_rules(LintProfile::Strict));
  auto codes = codes_by_pointer(report);
  EXPECT_EQ(codes["/materials/0" + kLegacy + "/specularFactor"],
            (std::set<std::string>{"PBR_DIELECTRIC_SPECULAR_CHROMATIC"}));
  EXPECT_EQ(codes["/materials/1/pbrMetallicRoughness/baseColorFactor"],
            (std::set<std::string>{"PBR_ALBEDO_TOO_BRIGHT"}));
  EXPECT_TRUE(codes["/materials/2/pbrMetallicRoughness/metallicFactor"].contains("PBR_PARTIAL_METALNESS"));
  EXPECT_TRUE(codes["/materials/2/pbrMetallicRoughness/roughnessFactor"].contains("PBR_ROUGHNESS_ZERO"));
  const auto high = issues_with(report, "PBR_DIELECTRIC_F0_TOO_HIGH");
  ASSERT_EQ(high.size(), 1u) << describe(problems(report));
  EXPECT_EQ(high[0].pointer, "/materials/3/extensions/KHR_materials_specular/specularColorFactor");
  EXPECT_NE(high[0].message.find("nearest to Aluminum"), std::string::npos) << high[0].message;
}

// An 8x4 base colour: 4 texels too dark (sRGB 10), 2 too bright (sRGB 252), the rest sRGB 128;
// metallicRoughness B (metalness) 128 in 10 texels, elsewhere 0, G 128 everywhere.
struct CoverageCase {
  static constexpr int kWidth = 8, kHeight = 4;
  static bool dark(int x, int y) { return y == 0 && x < 4; }
  static bool bright(int x, int y) { return y == 1 && x >= 6; }
  static bool partial(int x, int y) { return y >= 2 && (y == 2 || x < 2); }  // 8 + 2 texels
};

TEST(MaterialPlausibility, TextureCoverageCountsExactlyTheFailingTexelsAndPaintsThem) {
  AssetBuilder builder;
  std::vector<std::uint8_t> base, metal_rough;
  for (int y = 0; y < CoverageCase::kHeight; ++y)
    for (int x = 0; x < CoverageCase::kWidth; ++x) {
      const std::uint8_t v = CoverageCase::dark(x, y) ? 10 : CoverageCase::bright(x, y) ? 252 : 128;
      base.insert(base.end(), {v, v, v, 255});
      metal_rough.insert(metal_rough.end(), {0, 128, static_cast<std::uint8_t>(CoverageCase::partial(x, y) ? 128 : 0)});
    }
  const int base_texture = builder.add_png(CoverageCase::kWidth, CoverageCase::kHeight, 4, base);
  const int mr_texture = builder.add_png(CoverageCase::kWidth, CoverageCase::kHeight, 3, metal_rough);
  auto& material = builder.metal_rough(glm::vec4(1.0f), 1.0, 1.0);
  material.pbrMetallicRoughness.baseColorTexture.index = base_texture;
  material.pbrMetallicRoughness.metallicRoughnessTexture.index = mr_texture;

  ScratchDir scratch;
  MaterialCheckOptions options;
  options.textures = false;
  options.heatmaps_dir = scratch / "heatmaps";
  const long decoded_before = work_counters().images_decoded.load();
  const Report report = validate_in_memory(builder.asset(), builtin_rules(LintProfile::Strict), options);
  EXPECT_EQ(work_counters().images_decoded.load() - decoded_before, 2);

  auto only = [&](const std::string& code) {
    const auto found = issues_with(report, code);
    EXPECT_EQ(found.size(), 1u) << code << "\n" << describe(report.messages);
    return found.empty() ? Issue{} : found[0];
  };
  const Issue dark = only("PBR_ALBEDO_TOO_DARK");
  EXPECT_EQ(dark.pointer, "/materials/0/pbrMetallicRoughness/baseColorTexture");
  EXPECT_NE(dark.message.find("12.50% of 32 texels (8x4)"), std::string::npos) << dark.message;
  EXPECT_NE(dark.message.find("sRGB 10)"), std::string::npos) << dark.message;  // the extreme found
  const Issue bright = only("PBR_ALBEDO_TOO_BRIGHT");
  EXPECT_NE(bright.message.find("6.25% of 32 texels"), std::string::npos) << bright.message;
  EXPECT_NE(bright.message.find("sRGB 252)"), std::string::npos) << bright.message;
  const Issue partial = only("PBR_PARTIAL_METALNESS");
  EXPECT_EQ(partial.pointer, "/materials/0/pbrMetallicRoughness/metallicRoughnessTexture");
  EXPECT_NE(partial.message.find("31.25% of 32 texels"), std::string::npos) << partial.message;
  EXPECT_NE(partial.message.find("metalness 0.50"), std::string::npos) << partial.message;

  const fs::path heat_map = scratch / "heatmaps" / "built-in-memory-material0-texture0.png";
  ASSERT_TRUE(fs::exists(heat_map)) << describe(report.messages);
  const Pixels pixels = decode_image(*read_file(heat_map), heat_map.string());
  ASSERT_EQ(pixels.width, CoverageCase::kWidth);
  ASSERT_EQ(pixels.height, CoverageCase::kHeight);
  for (int y = 0; y < CoverageCase::kHeight; ++y)
    for (int x = 0; x < CoverageCase::kWidth; ++x) {
      std::array<int, 3> rgb{};
      for (int c = 0; c < 3; ++c)
        rgb[static_cast<size_t>(c)] = static_cast<int>(std::lround(pixels.at(x, y, c) * 255.0f));
      SCOPED_TRACE(std::to_string(x) + "," + std::to_string(y));
      if (CoverageCase::partial(x, y))
        EXPECT_EQ(rgb, (std::array<int, 3>{255, 255, 0}));  // out of range
      else if (CoverageCase::bright(x, y))
        EXPECT_EQ(rgb, (std::array<int, 3>{255, 0, 0}));  // too bright
      else if (CoverageCase::dark(x, y))
        EXPECT_EQ(rgb, (std::array<int, 3>{0, 0, 255}));  // too dark
      else {
        EXPECT_EQ(rgb[0], rgb[1]);  // passing: dimmed grey
        EXPECT_EQ(rgb[1], rgb[2]);
        EXPECT_LE(rgb[0], 127);
      }
    }
}

// Texels are judged once per distinct value within a material, in bands of rows on the pool; the
// count, the worst texel and the heat map must not depend on which texels repeat, where, or which
// band judged them. 1024x512 texels (two bands or more where the pool has two threads) with 65,536
// distinct values (base colour alpha = y and occlusion = x, which no check reads) overflow the
// verdict tables and collide in them; the darkest texel occurs once, in the first band.
TEST(MaterialPlausibility, RepeatedAndCollidingTexelsAreCountedExactlyAndTheWorstIsFound) {
  constexpr int kWidth = 1024, kHeight = 512;
  auto grey = [](int x, int y) -> std::uint8_t {
    if (x == 1000 && y == 5) return 3;  // the worst
    if ((x * 31 + y * 17) % 7 == 0) return 10;
    if ((x * 13 + y * 29) % 11 == 0) return 252;
    return 128;
  };
  AssetBuilder builder;
  std::vector<std::uint8_t> base, metal_rough;
  long dark = 0, bright = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const std::uint8_t v = grey(x, y);
      base.insert(base.end(), {v, v, v, static_cast<std::uint8_t>(y & 255)});
      metal_rough.insert(metal_rough.end(), {static_cast<std::uint8_t>(x & 255), 200, 0});
      dark += v <= 10, bright += v == 252;
    }
  auto& material = builder.metal_rough(glm::vec4(1.0f), 0.0, 1.0);
  material.pbrMetallicRoughness.baseColorTexture.index = builder.add_png(kWidth, kHeight, 4, base);
  material.pbrMetallicRoughness.metallicRoughnessTexture.index = builder.add_png(kWidth, kHeight, 3, metal_rough);

  ScratchDir scratch;
  MaterialCheckOptions options;
  options.textures = false;
  options.heatmaps_dir = scratch / "heatmaps";
  const Report report = validate_in_memory(builder.asset(), builtin_rules(LintProfile::Strict), options);
  auto coverage = [](long failing) {
    char text[64];
    std::snprintf(text, sizeof text, "%.2f%% of 524288 texels (1024x512)",
                  100.0 * static_cast<double>(failing) / 524288);
    return std::string(text);
  };
  const auto too_dark = issues_with(report, "PBR_ALBEDO_TOO_DARK");
  ASSERT_EQ(too_dark.size(), 1u) << describe(report.messages);
  EXPECT_NE(too_dark[0].message.find(coverage(dark)), std::string::npos) << too_dark[0].message;
  EXPECT_NE(too_dark[0].message.find("sRGB 3)"), std::string::npos) << too_dark[0].message;
  const auto too_bright = issues_with(report, "PBR_ALBEDO_TOO_BRIGHT");
  ASSERT_EQ(too_bright.size(), 1u) << describe(report.messages);
  EXPECT_NE(too_bright[0].message.find(coverage(bright)), std::string::npos) << too_bright[0].message;

  const fs::path heat_map = scratch / "heatmaps" / "built-in-memory-material0-texture0.png";
  ASSERT_TRUE(fs::exists(heat_map)) << describe(report.messages);
  const Pixels pixels = decode_image(*read_file(heat_map), heat_map.string());
  ASSERT_EQ(pixels.width, kWidth);
  long painted_dark = 0, painted_bright = 0, misplaced = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const bool blue = pixels.at(x, y, 2) == 1.0f && pixels.at(x, y, 0) == 0.0f;
      const bool red = pixels.at(x, y, 0) == 1.0f && pixels.at(x, y, 2) == 0.0f;
      painted_dark += blue, painted_bright += red;
      misplaced += blue != (grey(x, y) <= 10) || red != (grey(x, y) == 252);
    }
  EXPECT_EQ(painted_dark, dark);
  EXPECT_EQ(painted_bright, bright);
  EXPECT_EQ(misplaced, 0);
}

// Textures of different sizes are judged on the texels the converter bakes: the grid of the larger
// width and height, each texture resampled to it the way the bake resamples it. A 4x1 diffuse whose
// first column is black beside a 1x4 specular-glossiness map bakes at 4x4, so the black column is
// 4 of 16 texels; judged on the larger texture alone it would have been 1 of 4.
TEST(MaterialPlausibility, TexturesOfDifferentSizesAreJudgedOnTheGridTheConverterBakes) {
  AssetBuilder builder;
  const std::vector<std::uint8_t> diffuse{5, 5, 5, 255, 128, 128, 128, 255, 128, 128, 128, 255, 128, 128, 128, 255};
  std::vector<std::uint8_t> spec_gloss;
  for (int y = 0; y < 4; ++y) spec_gloss.insert(spec_gloss.end(), {56, 56, 56, 128});  // F0 0.04, glossiness 0.5
  const int diffuse_texture = builder.add_png(4, 1, 4, diffuse);
  const int spec_gloss_texture = builder.add_png(1, 4, 4, spec_gloss);
  tinygltf::Material& material = builder.spec_gloss(glm::vec4(1.0f), glm::vec3(1.0f), 1.0);
  tinygltf::Value::Object extension =
      material.extensions.at("KHR_materials_pbrSpecularGlossiness").Get<tinygltf::Value::Object>();
  extension["diffuseTexture"] = tinygltf::Value(tinygltf::Value::Object{{"index", tinygltf::Value(diffuse_texture)}});
  extension["specularGlossinessTexture"] =
      tinygltf::Value(tinygltf::Value::Object{{"index", tinygltf::Value(spec_gloss_texture)}});
  material.extensions["KHR_materials_pbrSpecularGlossiness"] = tinygltf::Value(extension);

  MaterialCheckOptions options;
  options.textures = false;
  const Report report = validate_in_memory(builder.asset(), builtin_rules(LintProfile::Strict), options);
  const auto dark = issues_with(report, "PBR_ALBEDO_TOO_DARK");
  ASSERT_EQ(dark.size(), 1u) << describe(report.messages);
  EXPECT_NE(dark[0].message.find("25.00% of 16 texels (4x4)"), std::string::npos) << dark[0].message;

  Asset converted = builder.asset();
  ConvertOptions convert_options;
  convert_options.target = Target::Metalness;
  (void)convert(converted, convert_options);
  const int base_color = converted.model.materials[0].pbrMetallicRoughness.baseColorTexture.index;
  ASSERT_GE(base_color, 0);
  const ImageHeader baked = read_image_header(
      encoded_image_bytes(converted, converted.model.textures[static_cast<size_t>(base_color)].source));
  EXPECT_EQ(baked.width, 4);
  EXPECT_EQ(baked.height, 4);

  // The grid is bounded as the bake is: above --max-image-pixels the texels go unchecked, and say so.
  const std::uint64_t limit = max_image_pixels();
  set_max_image_pixels(15);
  const Report bounded = validate_in_memory(builder.asset(), builtin_rules(LintProfile::Strict), options);
  set_max_image_pixels(limit);
  EXPECT_TRUE(issues_with(bounded, "PBR_ALBEDO_TOO_DARK").empty()) << describe(bounded.messages);
  const auto unchecked = issues_with(bounded, "PBR_TEXELS_NOT_CHECKED");
  ASSERT_EQ(unchecked.size(), 1u) << describe(bounded.messages);
  EXPECT_EQ(unchecked[0].pointer, "/materials/0");
  EXPECT_NE(unchecked[0].message.find("bake at 4x4, above the limit of 15 pixels"), std::string::npos)
      << unchecked[0].message;
}

TEST(MaterialPlausibility, AHeatMapsNameGivesBackItsAssetsStemAndNoOtherNameGivesOne) {
  for (const std::string stem : {"Box", "a-material1-texture2", "", "7"})
    for (const int material : {0, 7, 123})
      for (const int texture : {0, 45}) EXPECT_EQ(heat_map_stem(heat_map_name(stem, material, texture)), stem);
  for (const char* other : {"Box-material0-texture0.PNG", "Box-material-texture0.png", "Box-material0-texture.png",
                            "Box-material0-texture0.png.png", "Box-material+1-texture0.png", "Box-material0-texture0",
                            "material0-texture0.png", ".png"})
    EXPECT_EQ(heat_map_stem(other), std::nullopt) << other;
}

// Avocado's specular-glossiness map is black (F0 0) where the skin is: the reported coverage and
// the heat map's "too dark" texels are the same texels.
TEST(MaterialPlausibility, AvocadoSpecularMapCoverageMatchesItsHeatMap) {
  ScratchDir scratch;
  const Asset asset = load_asset(test::assets_dir() / "Avocado/specgloss/Avocado.gltf");
  MaterialCheckOptions options;
  options.textures = false;
  options.heatmaps_dir = scratch.path();
  const Report report = validate_in_memory(asset, builtin_rules(), options);
  const auto low = issues_with(report, "PBR_DIELECTRIC_F0_TOO_LOW");
  ASSERT_EQ(low.size(), 1u) << describe(report.messages);
  EXPECT_EQ(low[0].pointer, "/materials/0" + kLegacy + "/specularGlossinessTexture");
  const std::string& message = low[0].message;
  const double percent = std::stod(message.substr(message.find("): ") + 3));
  const auto maps = test::files_under(scratch.path());
  ASSERT_EQ(maps.size(), 1u);
  const Pixels heat = decode_image(*read_file(maps[0]), maps[0].string());
  ASSERT_EQ(heat.width, 2048);
  std::uint64_t blue = 0;
  for (int y = 0; y < heat.height; ++y)
    for (int x = 0; x < heat.width; ++x)
      blue += heat.at(x, y, 0) == 0.0f && heat.at(x, y, 1) == 0.0f && heat.at(x, y, 2) == 1.0f;
  EXPECT_NEAR(100.0 * static_cast<double>(blue) / (2048.0 * 2048.0), percent, 0.005) << message;
}

TEST(MaterialPlausibility, CoverageBelowTheThresholdIsNotReported) {
  AssetBuilder builder;
  std::vector<std::uint8_t> base;
  for (int i = 0; i < 200; ++i) {
    const std::uint8_t v = i == 0 ? 5 : 128;  // 0.5% of texels too dark, under the 1% default
    base.insert(base.end(), {v, v, v});
  }
  auto& material = builder.metal_rough(glm::vec4(1.0f), 0.0, 0.5);
  material.pbrMetallicRoughness.baseColorTexture.index = builder.add_png(20, 10, 3, base);
  EXPECT_TRUE(issues_with(validate_in_memory(builder.asset()), "PBR_ALBEDO_TOO_DARK").empty());
}

TEST(MaterialPlausibility, ImagesAreDecodedOnlyForEnabledTexelRules) {
  AssetBuilder builder;
  auto& material = builder.metal_rough(glm::vec4(1.0f), 0.0, 0.5);
  material.pbrMetallicRoughness.baseColorTexture.index = builder.add_png(2, 2, 3, std::vector<std::uint8_t>(12, 128));
  // Roughness reads no base colour: with only it enabled, nothing is decoded.
  RuleSet rules = builtin_rules();
  for (const auto& [code, rule] : builtin_rules().all())
    rules.mutable_rule(code).enabled = code == "PBR_ROUGHNESS_ZERO";
  const long before = work_counters().images_decoded.load();
  validate_in_memory(builder.asset(), rules);
  EXPECT_EQ(work_counters().images_decoded.load() - before, 0);
  // With every rule on, the one image is decoded once for material and texture checks together.
  validate_in_memory(builder.asset());
  EXPECT_EQ(work_counters().images_decoded.load() - before, 1);
}

// Every spec-gloss asset of ../shared, converted in-process: no material of the output has a PBR
// error that the same material of the input did not have.
TEST(MaterialPlausibility, ConversionAddsNoPbrErrorToAnySharedAsset) {
  ScratchDir scratch;
  std::vector<fs::path> inputs;
  for (const auto& entry : fs::recursive_directory_iterator(test::assets_dir())) {
    const std::string folder = entry.path().parent_path().filename().string();
    const std::string extension = entry.path().extension().string();
    if (folder.starts_with("specgloss") && (extension == ".gltf" || extension == ".glb"))
      inputs.push_back(entry.path());
  }
  ASSERT_GE(inputs.size(), 11u);
  auto errors_by_material = [](const Report& report) {
    std::map<std::string, std::set<std::string>> errors;  // "/materials/N" -> codes
    for (const Issue& issue : report.messages) {
      if (issue.severity != Severity::Error || !issue.code.starts_with("PBR_")) continue;
      const size_t end = issue.pointer.find('/', std::string("/materials/").size());
      errors[issue.pointer.substr(0, end)].insert(issue.code);
    }
    return errors;
  };
  int outputs = 0;
  for (const fs::path& input : inputs) {
    SCOPED_TRACE(input.string());
    MaterialCheckOptions options;
    options.textures = false;
    Asset asset = load_asset(input);
    const auto before = errors_by_material(validate_in_memory(asset, builtin_rules(), options));
    for (Target target : {Target::Metalness, Target::Specular}) {
      Asset converted = load_asset(input);
      ConvertOptions convert_options;
      convert_options.target = target;
      convert(converted, convert_options);
      const fs::path output = scratch / (std::to_string(outputs++) + input.extension().string());
      save_asset(converted, output);
      const Report after_report = validate_in_memory(load_asset(output), builtin_rules(), options);
      EXPECT_TRUE(issues_with(after_report, "PBR_LEGACY_SPEC_GLOSS").empty());
      for (const auto& [material, codes] : errors_by_material(after_report))
        for (const std::string& code : codes)
          EXPECT_TRUE(before.contains(material) && before.at(material).contains(code))
              << material << " " << code << " after converting to "
              << (target == Target::Metalness ? "metalness" : "specular");
    }
  }
}

TEST(MaterialPlausibility, UserConfigChangesSeveritiesThresholdsAndSilencesCodes) {
  ScratchDir scratch;
  const fs::path config = scratch / "config.yaml";
  test::write_text(config,
                   "override:\n  PBR_METAL_WITH_DIFFUSE: warning\n  PBR_ENERGY_NOT_CONSERVED: 2\n"
                   "ignore: [PBR_LEGACY_SPEC_GLOSS, PBR_ROUGHNESS_ZERO]\n"
                   "thresholds:\n  PBR_METAL_F0_TOO_DARK: {min_mean_f0: 0.4}\n");
  RuleSet rules = builtin_rules(LintProfile::Strict);
  IssuePolicy policy;
  apply_user_config(config, rules, policy);
  ValidateOptions options;
  options.steps = {ValidationStep::Materials};
  const Report defaults =
      validate_file(two_cylinder_engine(), "2CylinderEngine.gltf", builtin_rules(LintProfile::Strict), {}, options);
  const Report configured = validate_file(two_cylinder_engine(), "2CylinderEngine.gltf", rules, policy, options);

  ASSERT_FALSE(issues_with(defaults, "PBR_METAL_WITH_DIFFUSE").empty());
  EXPECT_EQ(issues_with(defaults, "PBR_METAL_WITH_DIFFUSE")[0].severity, Severity::Error);
  for (const Issue& issue : issues_with(configured, "PBR_METAL_WITH_DIFFUSE"))
    EXPECT_EQ(issue.severity, Severity::Warning);
  for (const Issue& issue : issues_with(configured, "PBR_ENERGY_NOT_CONSERVED"))
    EXPECT_EQ(issue.severity, Severity::Information);
  EXPECT_EQ(configured.count(Severity::Error), 0u);
  EXPECT_GT(defaults.count(Severity::Error), 0u);

  EXPECT_FALSE(issues_with(defaults, "PBR_LEGACY_SPEC_GLOSS").empty());
  EXPECT_TRUE(issues_with(configured, "PBR_LEGACY_SPEC_GLOSS").empty());
  EXPECT_TRUE(issues_with(configured, "PBR_ROUGHNESS_ZERO").empty());

  // Mean F0 0.443 (material 2) passes at 0.4; (0, 0.4, 0.4), mean 0.267, still fails.
  auto too_dark_at = [](const Report& report, int material) {
    for (const Issue& issue : issues_with(report, "PBR_METAL_F0_TOO_DARK"))
      if (issue.pointer.starts_with("/materials/" + std::to_string(material) + "/")) return true;
    return false;
  };
  EXPECT_TRUE(too_dark_at(defaults, 2));
  EXPECT_FALSE(too_dark_at(configured, 2));
  EXPECT_TRUE(too_dark_at(configured, 4));
  // The message names the bound that judged and that it is the config's, not the profile's.
  for (const Issue& issue : issues_with(configured, "PBR_METAL_F0_TOO_DARK"))
    EXPECT_NE(issue.message.find("darker than 0.400 (linear, mean of RGB; the config-adjusted strict profile's floor)"),
              std::string::npos)
        << issue.message;
  for (const Issue& issue : issues_with(defaults, "PBR_METAL_F0_TOO_DARK"))
    EXPECT_NE(issue.message.find("darker than 0.450 (linear, mean of RGB; the strict profile's floor)"),
              std::string::npos)
        << issue.message;
}

TEST(Materials, TheUvMappingNoteNamesTexturesCombinedAtEqualUvNeverASingleOne) {
  // A white base colour (too bright for a dielectric) through KHR_texture_transform alone: one
  // texture is checked texel by texel, so nothing was combined and no note says so. With a
  // metallicRoughness map read through another texCoord set, the two meet at equal UV: noted.
  const std::vector<std::uint8_t> white(16 * 3, 255);
  std::vector<std::uint8_t> rough;  // metalness 0, roughness 0.5
  for (int i = 0; i < 16; ++i) rough.insert(rough.end(), {0, 128, 0});
  for (const bool second_texture : {false, true}) {
    AssetBuilder builder;
    auto& material = builder.metal_rough(glm::vec4(1.0f), 0.0, 0.5);
    material.pbrMetallicRoughness.baseColorTexture.index = builder.add_png(4, 4, 3, white);
    tinygltf::Value::Object transform;
    transform["scale"] = numbers({2.0, 2.0});
    material.pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
        tinygltf::Value(std::move(transform));
    if (second_texture) {
      material.pbrMetallicRoughness.metallicRoughnessTexture.index = builder.add_png(4, 4, 3, rough);
      material.pbrMetallicRoughness.metallicRoughnessTexture.texCoord = 1;
    }
    const auto bright =
        issues_with(validate_in_memory(builder.asset(), builtin_rules(LintProfile::Strict)), "PBR_ALBEDO_TOO_BRIGHT");
    ASSERT_EQ(bright.size(), 1u) << second_texture;
    EXPECT_EQ(bright[0].message.find("combined at equal UV") != std::string::npos, second_texture) << bright[0].message;
  }
}

}  // namespace
}  // namespace gltf_pbr
