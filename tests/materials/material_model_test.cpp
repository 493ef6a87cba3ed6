// The effective material (core/material_model.hpp): colour spaces and channels of every texture
// role, each model's reflectance, and the pointers it names.
#include "core/material_model.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "core/color.hpp"
#include "core/error.hpp"
#include "core/image_header.hpp"
#include "material_test_support.hpp"

namespace gltf_pbr {
namespace {

using namespace test;  // the builders and report queries of the test support headers

TEST(MaterialModel, LegacyTexturesAreSrgbInRgbAndLinearInAlpha) {
  AssetBuilder builder;
  builder.spec_gloss(glm::vec4(1.0f), glm::vec3(1.0f), 1.0);
  MaterialInputs material = read_material_inputs(builder.asset().model, 0);
  ASSERT_EQ(material.model, MaterialModel::SpecGloss);
  TexelInputs texels;
  texels[TextureRole::Diffuse] = glm::vec4(0.5f, 0.5f, 0.5f, 0.3f);
  texels[TextureRole::SpecularGlossiness] = glm::vec4(0.2f, 0.2f, 0.2f, 0.25f);
  const SurfaceSample s = evaluate_surface(material, texels);
  const float specular = srgb_to_linear(0.2f);
  EXPECT_FLOAT_EQ(s.f0.r, specular);
  EXPECT_FLOAT_EQ(s.albedo.g, srgb_to_linear(0.5f));
  EXPECT_FLOAT_EQ(s.c_diff.b, srgb_to_linear(0.5f) * (1.0f - specular));  // c_diff = diffuse (1 - max(spec))
  EXPECT_FLOAT_EQ(s.roughness, 0.75f);                                    // 1 - glossiness, glossiness linear
}

// One reader, two strictnesses: what the tolerant reading (validate) takes as the spec default, the
// strict reading (convert) refuses, naming the value; on a well-formed material they agree.
TEST(MaterialModel, StrictReadingRefusesWhatTolerantReadingDefaultsAndNamesIt) {
  struct Case {
    const char* key;
    tinygltf::Value value;
    const char* pointer;
    const char* reason;
  };
  tinygltf::Value::Object no_index;
  no_index["texCoord"] = tinygltf::Value(0);
  tinygltf::Value::Object missing_texture, negative_texture;
  missing_texture["index"] = tinygltf::Value(7);
  negative_texture["index"] = tinygltf::Value(-5);
  const std::vector<Case> cases{
      {"diffuseFactor", tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(0.5), tinygltf::Value(0.5)}),
       "/diffuseFactor", "must be an array of 4 numbers"},
      {"specularFactor",
       tinygltf::Value(
           tinygltf::Value::Array{tinygltf::Value(0.5), tinygltf::Value(std::string("x")), tinygltf::Value(0.5)}),
       "/specularFactor/1", "not a number"},
      {"glossinessFactor", tinygltf::Value(std::numeric_limits<double>::infinity()), "/glossinessFactor",
       "factors must be finite"},
      {"diffuseTexture", tinygltf::Value(no_index), "/diffuseTexture", "textureInfo needs an integer index"},
      {"specularGlossinessTexture", tinygltf::Value(missing_texture), "/specularGlossinessTexture/index",
       "texture 7 does not exist"},
      {"diffuseTexture", tinygltf::Value(negative_texture), "/diffuseTexture/index", "texture -5 does not exist"},
  };
  const std::string extension = "/materials/0/extensions/KHR_materials_pbrSpecularGlossiness";
  for (const Case& c : cases) {
    AssetBuilder builder;
    tinygltf::Material& material = builder.spec_gloss(glm::vec4(0.25f), glm::vec3(0.5f), 0.5);
    tinygltf::Value::Object object =
        material.extensions.at("KHR_materials_pbrSpecularGlossiness").Get<tinygltf::Value::Object>();
    object[c.key] = c.value;
    material.extensions["KHR_materials_pbrSpecularGlossiness"] = tinygltf::Value(object);
    const MaterialInputs tolerant = read_material_inputs(builder.asset(), 0, MaterialReading::Tolerant);
    EXPECT_FALSE(tolerant.texture(TextureRole::Diffuse).present()) << c.key;
    EXPECT_FALSE(tolerant.texture(TextureRole::SpecularGlossiness).present()) << c.key;
    try {
      (void)read_material_inputs(builder.asset(), 0, MaterialReading::Strict);
      ADD_FAILURE() << c.key << ": the strict reading took it";
    } catch (const InputError& error) {
      EXPECT_EQ(error.pointer, extension + c.pointer) << c.key;
      EXPECT_NE(std::string(error.what()).find(c.reason), std::string::npos) << error.what();
    }
  }
  AssetBuilder builder;
  builder.spec_gloss(glm::vec4(0.25f, 0.5f, 0.75f, 1.0f), glm::vec3(0.1f, 0.2f, 0.3f), 0.4);
  const MaterialInputs strict = read_material_inputs(builder.asset(), 0, MaterialReading::Strict);
  const MaterialInputs tolerant = read_material_inputs(builder.asset().model, 0);
  EXPECT_EQ(strict.diffuse, tolerant.diffuse);
  EXPECT_EQ(strict.legacy_specular, tolerant.legacy_specular);
  EXPECT_EQ(strict.glossiness, tolerant.glossiness);
  EXPECT_EQ(strict.factor_pointers, tolerant.factor_pointers);
  EXPECT_EQ(strict.diffuse, glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
}

TEST(MaterialModel, MetallicRoughnessReadsGreenAndBlueLinearly) {
  AssetBuilder builder;
  builder.metal_rough(glm::vec4(0.8f, 0.6f, 0.4f, 1.0f), 0.5, 0.8);
  const MaterialInputs material = read_material_inputs(builder.asset().model, 0);
  TexelInputs texels;
  texels[TextureRole::BaseColor] = glm::vec4(0.5f, 1.0f, 1.0f, 1.0f);
  texels[TextureRole::MetallicRoughness] = glm::vec4(0.9f, 0.5f, 0.25f, 1.0f);
  const SurfaceSample s = evaluate_surface(material, texels);
  EXPECT_FLOAT_EQ(s.roughness, 0.4f);
  EXPECT_FLOAT_EQ(s.metalness, 0.125f);
  const float base_r = 0.8f * srgb_to_linear(0.5f);
  EXPECT_FLOAT_EQ(s.f0.r, 0.04f + (base_r - 0.04f) * 0.125f);      // mix(0.04, base, m)
  EXPECT_NEAR(s.c_diff.g, 0.6f * (1.0f - 0.125f) * 0.96f, 1e-6f);  // base (1 - m)(1 - 0.04)
  EXPECT_EQ(material.factor_pointers.at("metallicFactor"), "/materials/0/pbrMetallicRoughness/metallicFactor");
}

TEST(MaterialModel, SpecularExtensionUsesSrgbColourAndLinearAlphaWeight) {
  AssetBuilder builder;
  tinygltf::Value::Object specular;
  specular["specularFactor"] = tinygltf::Value(0.5);
  auto& written = builder.metal_rough(glm::vec4(0.5f, 0.5f, 0.5f, 1.0f), 0.0, 0.5);
  written.extensions["KHR_materials_specular"] = tinygltf::Value(specular);
  const MaterialInputs material = read_material_inputs(builder.asset().model, 0);
  EXPECT_EQ(material.factor_pointers.at("specularFactor"),
            "/materials/0/extensions/KHR_materials_specular/specularFactor");
  EXPECT_EQ(material.factor_pointers.at("specularColorFactor"), "/materials/0/extensions/KHR_materials_specular");
  TexelInputs texels;
  texels[TextureRole::SpecularColor] = glm::vec4(0.5f, 1.0f, 1.0f, 0.1f);  // alpha unused
  texels[TextureRole::Specular] = glm::vec4(0.1f, 0.1f, 0.1f, 0.5f);       // RGB unused
  const SurfaceSample s = evaluate_surface(material, texels);
  // F0 = min(0.04 * colour, 1) * specular, with ior 1.5's 0.04.
  EXPECT_NEAR(s.dielectric_f0.r, 0.04f * srgb_to_linear(0.5f) * 0.25f, 1e-6f);
  EXPECT_NEAR(s.dielectric_f0.g, 0.04f * 0.25f, 1e-6f);
  // A core-only viewer ignores the extension: F0 0.04.
  EXPECT_FLOAT_EQ(evaluate_surface(material, texels, /*core_only=*/true).dielectric_f0.r, 0.04f);
}

TEST(ImageHeader, PngSizeAndChannelsAreReadWithoutDecoding) {
  std::vector<std::uint8_t> texels(13 * 7 * 3);
  for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = static_cast<std::uint8_t>(i * 37);  // not grey
  const Bytes png = encode_png(texels, 13, 7, 3, 1);
  const ImageHeader header = read_image_header(png);
  EXPECT_EQ(header.format, ImageFormat::Png);
  EXPECT_EQ(header.problem, HeaderProblem::None);
  EXPECT_EQ(header.width, 13);
  EXPECT_EQ(header.height, 7);
  EXPECT_EQ(header.channels, "rgb");
  const ImageHeader cut = read_image_header(std::span(png).first(png.size() - 4));  // inside IEND
  EXPECT_EQ(cut.problem, HeaderProblem::Truncated);
  EXPECT_EQ(read_image_header(std::vector<std::uint8_t>{1, 2, 3}).format, ImageFormat::Unknown);
  EXPECT_EQ(read_image_header(std::vector<std::uint8_t>{1, 2, 3}).width, -1);
}

}  // namespace
}  // namespace gltf_pbr
