// Texture checks (IMAGE_*): normal-map texels, constant images, empty used channels, resolution
// without detail and power-of-two sizes, on images built in memory and on shared assets.
#include <gtest/gtest.h>

#include "core/image_header.hpp"
#include "core/material_model.hpp"
#include "material_test_support.hpp"
#include "test_support.hpp"

namespace gltf_pbr {
namespace {

using namespace test;  // the builders and report queries of the test support headers

Report texture_checks(const Asset& asset) {
  MaterialCheckOptions options;
  options.materials = false;
  Report report;
  validate_materials(asset, builtin_rules(), options, report);
  return report;
}

std::uint8_t encode_normal(float n) { return static_cast<std::uint8_t>(std::lround((n * 0.5f + 0.5f) * 255.0f)); }

TEST(TextureChecks, NormalMapTexelsOffUnitLengthOrBackFacingAreCounted) {
  // 10x10: 5 texels of length ~0.5 (grey 191, 128, 128 -> (0.5, 0, 0)), 3 with z < 0, the rest flat.
  std::vector<std::uint8_t> texels;
  for (int i = 0; i < 100; ++i) {
    if (i < 5)
      texels.insert(texels.end(), {encode_normal(0.5f), encode_normal(0.0f), encode_normal(0.0f)});
    else if (i < 8)
      texels.insert(texels.end(), {encode_normal(0.0f), encode_normal(0.6f), encode_normal(-0.8f)});
    else
      texels.insert(texels.end(), {128, 128, 255});
  }
  AssetBuilder builder;
  const int normal = builder.add_png(10, 10, 3, texels);
  builder.metal_rough(glm::vec4(0.5f, 0.5f, 0.5f, 1.0f), 0.0, 0.5).normalTexture.index = normal;
  const Report report = texture_checks(builder.asset());
  const auto not_unit = issues_with(report, "IMAGE_NORMAL_NOT_UNIT");
  ASSERT_EQ(not_unit.size(), 1u) << describe(report.messages);
  EXPECT_EQ(not_unit[0].pointer, "/materials/0/normalTexture");
  EXPECT_NE(not_unit[0].message.find("5.00% of 100 texels"), std::string::npos) << not_unit[0].message;
  const auto back = issues_with(report, "IMAGE_NORMAL_BACK_FACING");
  ASSERT_EQ(back.size(), 1u) << describe(report.messages);
  EXPECT_NE(back[0].message.find("3.00% of 100 texels"), std::string::npos) << back[0].message;
}

TEST(TextureChecks, ConstantImageCouldBeAFactorAndEmptyUsedChannelsAreNamed) {
  AssetBuilder builder;
  // metallicRoughness packed as ORM: occlusion in R varies, G and B empty.
  std::vector<std::uint8_t> orm;
  for (int i = 0; i < 64; ++i) orm.insert(orm.end(), {static_cast<std::uint8_t>(i * 4), 0, 0});
  auto& material = builder.metal_rough(glm::vec4(1.0f), 1.0, 1.0);
  material.pbrMetallicRoughness.metallicRoughnessTexture.index = builder.add_png(8, 8, 3, orm);
  std::vector<std::uint8_t> constant_rgb;
  for (int i = 0; i < 16; ++i) constant_rgb.insert(constant_rgb.end(), {200, 120, 40});
  material.pbrMetallicRoughness.baseColorTexture.index = builder.add_png(4, 4, 3, constant_rgb);
  const Report report = texture_checks(builder.asset());

  const auto constant = issues_with(report, "IMAGE_CONSTANT");
  ASSERT_EQ(constant.size(), 1u) << describe(report.messages);
  EXPECT_EQ(constant[0].pointer, "/images/1");
  EXPECT_NE(constant[0].message.find("(200, 120, 40)"), std::string::npos) << constant[0].message;

  const auto empty = issues_with(report, "IMAGE_CHANNEL_EMPTY");
  ASSERT_EQ(empty.size(), 2u) << describe(report.messages);
  EXPECT_EQ(empty[0].pointer, "/materials/0/pbrMetallicRoughness/metallicRoughnessTexture");
  EXPECT_NE(empty[0].message.find("G (roughness)"), std::string::npos);
  EXPECT_NE(empty[1].message.find("B (metalness)"), std::string::npos);
  EXPECT_NE(empty[0].message.find("while R has content"), std::string::npos) << empty[0].message;
}

TEST(TextureChecks, GreyImagesAreCheckedAsTheRgbTheyAreSampledAs) {
  // glTF samples a grey PNG as R = G = B: a black grey metallicRoughness map has empty G and B, and
  // a mid-grey normal map decodes to (0.004, 0.004, 0.004), far from unit length.
  AssetBuilder builder;
  auto& material = builder.metal_rough(glm::vec4(1.0f), 1.0, 1.0);
  material.pbrMetallicRoughness.metallicRoughnessTexture.index =
      builder.add_png(8, 8, 1, std::vector<std::uint8_t>(64, 0));
  material.normalTexture.index = builder.add_png(8, 8, 1, std::vector<std::uint8_t>(64, 128));
  const Report report = texture_checks(builder.asset());
  const auto empty = issues_with(report, "IMAGE_CHANNEL_EMPTY");
  ASSERT_EQ(empty.size(), 2u) << describe(report.messages);
  EXPECT_NE(empty[0].message.find("G (roughness)"), std::string::npos);
  EXPECT_NE(empty[1].message.find("B (metalness)"), std::string::npos);
  EXPECT_EQ(issues_with(report, "IMAGE_NORMAL_NOT_UNIT").size(), 1u) << describe(report.messages);
}

TEST(TextureChecks, SmoothImageIsLargerThanNeededAndNoiseIsNot) {
  AssetBuilder builder;
  std::vector<std::uint8_t> smooth, noise;
  std::uint32_t state = 12345;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      smooth.insert(smooth.end(), {static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y), 90});
      state = state * 1664525u + 1013904223u;  // Numerical Recipes LCG
      noise.insert(noise.end(), {static_cast<std::uint8_t>(state >> 24), 0, 0});
    }
  auto& a = builder.metal_rough(glm::vec4(1.0f), 0.0, 0.5);
  a.pbrMetallicRoughness.baseColorTexture.index = builder.add_png(128, 128, 3, smooth);
  auto& b = builder.metal_rough(glm::vec4(1.0f), 0.0, 0.5);
  b.pbrMetallicRoughness.baseColorTexture.index = builder.add_png(128, 128, 3, noise);
  const Report report = texture_checks(builder.asset());
  const auto larger = issues_with(report, "IMAGE_LARGER_THAN_NEEDED");
  ASSERT_EQ(larger.size(), 1u) << describe(report.messages);
  EXPECT_EQ(larger[0].pointer, "/images/0");
  EXPECT_NE(larger[0].message.find("64x64 would do"), std::string::npos) << larger[0].message;
}

TEST(TextureChecks, NonPowerOfTwoSizeIsReadFromTheHeaderWithoutDecoding) {
  const Asset asset =
      load_asset(test::assets_dir() / "BoxTexturedNonPowerOfTwo/specgloss/BoxTexturedNonPowerOfTwo.gltf");
  RuleSet rules = builtin_rules();
  for (const auto& [code, rule] : builtin_rules().all())
    rules.mutable_rule(code).enabled = code == "IMAGE_NPOT_DIMENSIONS";
  const long before = work_counters().images_decoded.load();
  Report report;
  validate_materials(asset, rules, MaterialCheckOptions{}, report);
  EXPECT_EQ(work_counters().images_decoded.load() - before, 0);
  const auto npot = issues_with(report, "IMAGE_NPOT_DIMENSIONS");
  ASSERT_EQ(npot.size(), 1u) << describe(report.messages);
  EXPECT_NE(npot[0].message.find("211x211"), std::string::npos) << npot[0].message;
}

TEST(TextureChecks, JpegSizeIsReadFromItsFrameHeader) {
  const Asset asset = load_asset(test::assets_dir() / "CesiumMan/specgloss/CesiumMan.gltf");
  ASSERT_FALSE(asset.model.images.empty());
  const auto bytes = encoded_image_bytes(asset, 0);
  ASSERT_EQ(image_format_of(bytes), ImageFormat::Jpeg);
  const ImageHeader header = read_image_header(bytes);
  const Pixels pixels = decode_image(bytes, "CesiumMan image 0");
  EXPECT_EQ(header.width, pixels.width);
  EXPECT_EQ(header.height, pixels.height);
}

TEST(TextureChecks, UndecodableImageIsReportedOnceAndItsTexelsSkipped) {
  AssetBuilder builder;
  auto& material = builder.metal_rough(glm::vec4(1.0f), 0.0, 0.5);
  material.pbrMetallicRoughness.baseColorTexture.index = builder.add_png(2, 2, 3, std::vector<std::uint8_t>(12, 0));
  material.normalTexture.index = material.pbrMetallicRoughness.baseColorTexture.index;
  builder.asset().model.images[0].image = {0x89, 'P', 'N', 'G', 1, 2, 3};  // truncated PNG
  Report report;
  validate_materials(builder.asset(), builtin_rules(), MaterialCheckOptions{}, report);
  const auto undecodable = issues_with(report, "IMAGE_UNDECODABLE");
  ASSERT_EQ(undecodable.size(), 1u) << describe(report.messages);
  EXPECT_EQ(undecodable[0].pointer, "/images/0");
  // Its black texels were never read, and the white factor alone is not what renders.
  EXPECT_TRUE(issues_with(report, "PBR_ALBEDO_TOO_DARK").empty());
  EXPECT_TRUE(issues_with(report, "PBR_ALBEDO_TOO_BRIGHT").empty());
}

TEST(TextureChecks, Ktx2OnlyTexturesAreSaidOnceToGoUncheckedAndFallbacksAreChecked) {
  AssetBuilder builder;
  auto& material = builder.metal_rough(glm::vec4(1.0f), 0.0, 0.5);
  tinygltf::Model& model = builder.asset().model;
  // Two textures with only a KTX2 image (KHR_texture_basisu, no source) on two slots: one note.
  model.images.emplace_back().uri = "a.ktx2";
  model.images.emplace_back().uri = "b.ktx2";
  for (int image : {0, 1}) {
    tinygltf::Texture texture;
    texture.extensions["KHR_texture_basisu"] =
        tinygltf::Value(tinygltf::Value::Object{{"source", tinygltf::Value(image)}});
    model.textures.push_back(texture);
  }
  material.pbrMetallicRoughness.baseColorTexture.index = 0;
  material.normalTexture.index = 1;
  const Report report = texture_checks(builder.asset());
  const auto skipped = issues_with(report, "IMAGE_KTX2_NOT_CHECKED");
  ASSERT_EQ(skipped.size(), 1u) << describe(report.messages);
  EXPECT_EQ(skipped[0].pointer, "/materials/0/pbrMetallicRoughness/baseColorTexture");
  EXPECT_NE(skipped[0].message.find("skipped 2 KTX2 image(s)"), std::string::npos) << skipped[0].message;
  // Near miss: with a PNG fallback as its source, the texture's texels are read, and nothing is said.
  AssetBuilder with_fallback;
  auto& other = with_fallback.metal_rough(glm::vec4(1.0f), 0.0, 0.5);
  other.pbrMetallicRoughness.baseColorTexture.index = with_fallback.add_png(2, 2, 3, std::vector<std::uint8_t>(12, 90));
  with_fallback.asset().model.textures[0].extensions["KHR_texture_basisu"] =
      tinygltf::Value(tinygltf::Value::Object{{"source", tinygltf::Value(0)}});
  EXPECT_TRUE(issues_with(texture_checks(with_fallback.asset()), "IMAGE_KTX2_NOT_CHECKED").empty());
}

TEST(TextureChecks, AvocadoNormalMapAndTexturesPass) {
  const Asset asset = load_asset(test::assets_dir() / "Avocado/specgloss/Avocado.gltf");
  const Report report = texture_checks(asset);
  EXPECT_TRUE(test::problems(report).empty()) << describe(report.messages);
}

}  // namespace
}  // namespace gltf_pbr
