// Texture baking at the extremes: tiny, odd-sized and mismatched textures, JPEG and palette PNG
// inputs, alpha, constant results, the reused diffuse, the roughness/metalness channels and
// KHR_texture_transform. Small spec-gloss assets are built in code, saved with save_asset and
// loaded back with load_asset, so the real loader path is used.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <numeric>
#include <random>
#include <set>

#include "converter/bake.hpp"
#include "converter/convert.hpp"
#include "core/color.hpp"
#include "core/image.hpp"
#include "core/image_header.hpp"
#include "test_support.hpp"

namespace gltf_pbr {
namespace {

using test::assets_dir;
using test::files_under;
using test::ScratchDir;

using test::kSpecGloss;
using test::numbers;
constexpr const char* kTextureTransform = "KHR_texture_transform";

using Texel = std::array<std::uint8_t, 4>;

// 8-bit texels, interleaved, built from a function of (x, y).
struct Texels {
  int width = 0, height = 0, channels = 4;
  std::vector<std::uint8_t> values;
  Texels(int w, int h, int c, const std::function<Texel(int, int)>& texel) : width(w), height(h), channels(c) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Texel t = texel(x, y);
        values.insert(values.end(), t.begin(), t.begin() + c);
      }
  }
  Texel at(int x, int y) const {
    Texel t{0, 0, 0, 255};
    const size_t i =
        (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * static_cast<size_t>(channels);
    for (int c = 0; c < channels; ++c) t[static_cast<size_t>(c)] = values[i + static_cast<size_t>(c)];
    return t;
  }
};

// A legacy document with one spec-gloss material, built up by the test.
class SpecGlossModel {
 public:
  SpecGlossModel() {
    model_.asset.version = "2.0";
    model_.extensionsUsed.push_back(kSpecGloss);
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    model_.samplers.push_back(sampler);
  }

  // Adds encoded image bytes and a texture using them; returns the texture index.
  int add_encoded(Bytes bytes, const std::string& mime_type, const std::string& name) {
    tinygltf::Image image;
    image.name = name;
    image.mimeType = mime_type;
    image.as_is = true;
    image.image = std::move(bytes);
    model_.images.push_back(std::move(image));
    tinygltf::Texture texture;
    texture.source = static_cast<int>(model_.images.size()) - 1;
    texture.sampler = 0;
    model_.textures.push_back(texture);
    return static_cast<int>(model_.textures.size()) - 1;
  }
  int add_png(const Texels& t, const std::string& name) {
    return add_encoded(encode_png(t.values, t.width, t.height, t.channels, 6), "image/png", name);
  }

  SpecGlossModel& diffuse_texture(int texture, const tinygltf::Value::Object& transform = {}) {
    extension_["diffuseTexture"] = texture_info(texture, transform);
    return *this;
  }
  SpecGlossModel& spec_gloss_texture(int texture, const tinygltf::Value::Object& transform = {}) {
    extension_["specularGlossinessTexture"] = texture_info(texture, transform);
    return *this;
  }
  SpecGlossModel& factor(const std::string& key, tinygltf::Value value) {
    extension_[key] = std::move(value);
    return *this;
  }

  // Saves the document as `file` (.gltf or .glb) and loads it back.
  Asset save_and_load(const fs::path& file) {
    Asset asset;
    asset.path = file.parent_path() / "built-in-memory.gltf";  // never written
    asset.model = model_;
    tinygltf::Material material;
    material.name = "legacy";
    material.emissiveFactor = {0.0, 0.0, 0.0};
    material.extensions[kSpecGloss] = tinygltf::Value(extension_);
    asset.model.materials.push_back(material);
    save_asset(asset, file);
    return load_asset(file);
  }

 private:
  tinygltf::Value texture_info(int texture, const tinygltf::Value::Object& transform) {
    tinygltf::Value::Object info;
    info["index"] = tinygltf::Value(texture);
    if (!transform.empty()) {
      tinygltf::Value::Object extensions;
      extensions[kTextureTransform] = tinygltf::Value(transform);
      info["extensions"] = tinygltf::Value(std::move(extensions));
      if (std::find(model_.extensionsUsed.begin(), model_.extensionsUsed.end(), kTextureTransform) ==
          model_.extensionsUsed.end())
        model_.extensionsUsed.push_back(kTextureTransform);
    }
    return tinygltf::Value(std::move(info));
  }

  tinygltf::Model model_;
  tinygltf::Value::Object extension_;
};

// Converts, saves the result as `output` (in a scratch folder, never beside a shared asset) and
// loads that back.
Asset convert_save_reload(Asset& asset, const fs::path& output, ConversionReport* report = nullptr,
                          const ConvertOptions& options = {}) {
  const ConversionReport r = convert(asset, options);
  if (report) *report = r;
  save_asset(asset, output);
  return load_asset(output);
}

Pixels texture_pixels(const Asset& asset, int texture) {
  const int image = asset.model.textures.at(static_cast<size_t>(texture)).source;
  return decode_image(encoded_image_bytes(asset, image), pointer("images", image));
}

std::vector<std::uint8_t> texture_bytes(const Asset& asset, int texture) {
  const std::span<const std::uint8_t> bytes =
      encoded_image_bytes(asset, asset.model.textures.at(static_cast<size_t>(texture)).source);
  return {bytes.begin(), bytes.end()};
}

std::uint8_t to_byte(float unit) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(unit, 0.0f, 1.0f) * 255.0f));
}
std::uint8_t byte_at(const Pixels& p, int x, int y, int c) { return to_byte(p.at(x, y, c)); }

// What one texel bakes to: baseColor sRGB RGB + alpha, and metallicRoughness (0, G roughness,
// B metalness), from the solver itself (the legacy texture encodings of DESIGN.md, "Conversion").
struct Expected {
  Texel base_color;
  std::array<std::uint8_t, 3> metal_rough;
};
Expected expected_texel(Texel diffuse, Texel spec_gloss) {
  SpecGloss legacy;
  for (int c = 0; c < 3; ++c) {
    legacy.diffuse[c] = srgb8_to_linear(diffuse[static_cast<size_t>(c)]);
    legacy.specular[c] = srgb8_to_linear(spec_gloss[static_cast<size_t>(c)]);
  }
  legacy.glossiness = spec_gloss[3] / 255.0f;
  const MetalRough m = solve(legacy);
  Expected e;
  for (int c = 0; c < 3; ++c) e.base_color[static_cast<size_t>(c)] = to_byte(linear_to_srgb(m.base[c]));
  e.base_color[3] = diffuse[3];
  e.metal_rough = {0, to_byte(1.0f - legacy.glossiness), to_byte(m.metalness)};
  return e;
}

// A diffuse that varies smoothly, and a specular-glossiness map that runs from plastic (F0 0.04,
// sRGB 56) to iron (sRGB ~198) across x, with glossiness down y.
Texel ramp_diffuse(int x, int y, int w, int h) {
  return {static_cast<std::uint8_t>(40 + 200 * x / std::max(1, w - 1)),
          static_cast<std::uint8_t>(30 + 150 * y / std::max(1, h - 1)), 90, 255};
}
Texel ramp_spec_gloss(int x, int y, int w, int h) {
  const auto s = static_cast<std::uint8_t>(56 + 142 * x / std::max(1, w - 1));
  return {s, s, s, static_cast<std::uint8_t>(255 * y / std::max(1, h - 1))};
}

// Every metalness value the solve gives written as it is (no fewer_metalness_levels), for the
// tests that compare a bake texel for texel with the solver.
ConvertOptions every_metalness_value() {
  ConvertOptions options;
  options.metalness_tolerance = 0;
  return options;
}

// Both baked textures hold, texel for texel, what the solver gives for the inputs (±1 for the
// rounding of the PNG round trip); converted with every_metalness_value().
void expect_baked(const Asset& converted, const Texels& diffuse, const Texels& spec_gloss) {
  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  ASSERT_GE(pbr.baseColorTexture.index, 0);
  ASSERT_GE(pbr.metallicRoughnessTexture.index, 0);
  const Pixels base = texture_pixels(converted, pbr.baseColorTexture.index);
  const Pixels mr = texture_pixels(converted, pbr.metallicRoughnessTexture.index);
  ASSERT_EQ(base.width, diffuse.width);
  ASSERT_EQ(base.height, diffuse.height);
  ASSERT_EQ(mr.width, diffuse.width);
  ASSERT_EQ(mr.height, diffuse.height);
  for (int y = 0; y < diffuse.height; ++y)
    for (int x = 0; x < diffuse.width; ++x) {
      const Expected e = expected_texel(diffuse.at(x, y), spec_gloss.at(x, y));
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(byte_at(base, x, y, c), e.base_color[static_cast<size_t>(c)], 1) << x << "," << y << " base " << c;
        EXPECT_NEAR(byte_at(mr, x, y, c), e.metal_rough[static_cast<size_t>(c)], 1) << x << "," << y << " mr " << c;
      }
    }
}

bool no_spec_gloss(const Asset& asset) {
  for (const auto& material : asset.model.materials)
    if (material.extensions.count(kSpecGloss)) return false;
  return std::find(asset.model.extensionsUsed.begin(), asset.model.extensionsUsed.end(), kSpecGloss) ==
         asset.model.extensionsUsed.end();
}

// ---------------------------------------------------------------------------------------------
// Sizes
// ---------------------------------------------------------------------------------------------

TEST(Textures, OneByOneDiffuseTextureBecomesFactors) {
  ScratchDir scratch;
  const Texels diffuse(1, 1, 4, [](int, int) { return Texel{200, 120, 40, 255}; });
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(diffuse, "diffuse")).factor("specularFactor", numbers({0.5, 0.5, 0.5}));
  built.factor("glossinessFactor", tinygltf::Value(0.6));
  Asset asset = built.save_and_load(scratch / "tiny.gltf");

  ConversionReport report;
  const Asset converted = convert_save_reload(asset, scratch / "converted" / asset.path.filename(), &report);
  ASSERT_EQ(report.materials.size(), 1u);
  EXPECT_EQ(report.materials[0].outcome, MaterialOutcome::Metalness);
  EXPECT_EQ(report.materials[0].texels, 1);
  EXPECT_EQ(report.textures_baked, 0);
  EXPECT_TRUE(no_spec_gloss(converted));
  EXPECT_TRUE(converted.model.images.empty());
  EXPECT_TRUE(converted.model.textures.empty());

  // The specular factor enters the solve as it is, not through an 8-bit texel; the result is
  // stored as 8-bit texels first, then found constant and written as factors.
  SpecGloss legacy;
  for (int c = 0; c < 3; ++c) legacy.diffuse[c] = srgb8_to_linear(diffuse.at(0, 0)[static_cast<size_t>(c)]);
  legacy.specular = glm::vec3(0.5f);
  legacy.glossiness = 0.6f;
  const MetalRough expected = solve(legacy);
  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  EXPECT_EQ(pbr.baseColorTexture.index, -1);
  EXPECT_EQ(pbr.metallicRoughnessTexture.index, -1);
  ASSERT_EQ(pbr.baseColorFactor.size(), 4u);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(pbr.baseColorFactor[static_cast<size_t>(c)], srgb8_to_linear(to_byte(linear_to_srgb(expected.base[c]))),
                1e-4)
        << c;
  EXPECT_DOUBLE_EQ(pbr.baseColorFactor[3], 1.0);
  EXPECT_NEAR(pbr.metallicFactor, to_byte(expected.metalness) / 255.0, 1e-4);
  EXPECT_NEAR(pbr.roughnessFactor, 0.4, 1.0 / 255);
  EXPECT_GT(pbr.metallicFactor, 0.0);  // F0 0.5 is metal-like: not the dielectric fallback
}

TEST(Textures, NonPowerOfTwoTexturesBakeAtTheirOwnSizeTexelForTexel) {
  ScratchDir scratch;
  constexpr int w = 13, h = 7;
  const Texels diffuse(w, h, 4, [](int x, int y) { return ramp_diffuse(x, y, w, h); });
  const Texels spec_gloss(w, h, 4, [](int x, int y) { return ramp_spec_gloss(x, y, w, h); });
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(diffuse, "diffuse")).spec_gloss_texture(built.add_png(spec_gloss, "specGloss"));
  Asset asset = built.save_and_load(scratch / "npot.gltf");

  ConversionReport report;
  const Asset converted =
      convert_save_reload(asset, scratch / "converted" / asset.path.filename(), &report, every_metalness_value());
  ASSERT_EQ(report.materials.size(), 1u);
  EXPECT_EQ(report.materials[0].texels, w * h);
  EXPECT_EQ(report.textures_baked, 2);
  EXPECT_EQ(report.images_decoded, 2);
  EXPECT_TRUE(no_spec_gloss(converted));
  expect_baked(converted, diffuse, spec_gloss);
  // Both inputs are gone; only the two baked images remain.
  EXPECT_EQ(converted.model.images.size(), 2u);
}

TEST(Textures, DiffuseAndSpecGlossOfDifferentSizesBakeAtTheLargerSize) {
  ScratchDir scratch;
  struct Case {
    int diffuse_w, diffuse_h, spec_w, spec_h, want_w, want_h;
  };
  for (const Case c : {Case{8, 4, 32, 16, 32, 16}, Case{32, 16, 8, 4, 32, 16}, Case{16, 4, 5, 12, 16, 12}}) {
    SCOPED_TRACE(std::to_string(c.diffuse_w) + "x" + std::to_string(c.diffuse_h) + " and " + std::to_string(c.spec_w) +
                 "x" + std::to_string(c.spec_h));
    const Texels diffuse(c.diffuse_w, c.diffuse_h, 4,
                         [&](int x, int y) { return ramp_diffuse(x, y, c.diffuse_w, c.diffuse_h); });
    const Texels spec_gloss(c.spec_w, c.spec_h, 4,
                            [&](int x, int y) { return ramp_spec_gloss(x, y, c.spec_w, c.spec_h); });
    SpecGlossModel built;
    built.diffuse_texture(built.add_png(diffuse, "diffuse")).spec_gloss_texture(built.add_png(spec_gloss, "specGloss"));
    Asset asset =
        built.save_and_load(scratch / (std::to_string(c.diffuse_w) + "-" + std::to_string(c.spec_w)) / "sizes.gltf");

    ConversionReport report;
    const Asset converted =
        convert_save_reload(asset, scratch / "converted" / asset.path.parent_path().filename() / "sizes.gltf", &report);
    EXPECT_EQ(report.materials.at(0).texels, c.want_w * c.want_h);
    const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
    ASSERT_GE(pbr.baseColorTexture.index, 0);
    ASSERT_GE(pbr.metallicRoughnessTexture.index, 0);
    for (int texture : {pbr.baseColorTexture.index, pbr.metallicRoughnessTexture.index}) {
      const Pixels baked = texture_pixels(converted, texture);
      EXPECT_EQ(baked.width, c.want_w);
      EXPECT_EQ(baked.height, c.want_h);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Input encodings
// ---------------------------------------------------------------------------------------------

TEST(Textures, JpegDiffuseOfCesiumManBakesToAJpegAtTheJpegSize) {
  ScratchDir scratch;
  const fs::path input = assets_dir() / "CesiumMan" / "specgloss" / "CesiumMan.gltf";
  const auto jpeg = read_file(input.parent_path() / "CesiumMan.jpg");
  ASSERT_TRUE(jpeg);
  const Pixels source = decode_image(*jpeg, "CesiumMan.jpg");
  EXPECT_EQ(source.channels, 3);
  EXPECT_EQ(source.bits, 8);

  Asset asset = load_asset(input);
  ConversionReport report;
  const Asset converted = convert_save_reload(asset, scratch / "converted" / "CesiumMan.gltf", &report);
  ASSERT_EQ(report.materials.size(), 1u);
  EXPECT_EQ(report.materials[0].outcome, MaterialOutcome::Metalness);
  // The diffuse, and the baked JPEG, whose decode the error is measured on.
  EXPECT_EQ(report.images_decoded, 2);
  EXPECT_EQ(report.materials[0].texels, static_cast<long long>(source.width) * source.height);

  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  ASSERT_GE(pbr.baseColorTexture.index, 0);
  const int image = converted.model.textures.at(static_cast<size_t>(pbr.baseColorTexture.index)).source;
  // A lossy source stays lossy (converter/convert.cpp): an opaque JPEG diffuse bakes to JPEG.
  EXPECT_EQ(image_format_of(encoded_image_bytes(converted, image)), ImageFormat::Jpeg);
  const Pixels base = texture_pixels(converted, pbr.baseColorTexture.index);
  EXPECT_EQ(base.width, source.width);
  EXPECT_EQ(base.height, source.height);
  EXPECT_EQ(base.channels, 3);  // the JPEG has no alpha, so neither has the baked baseColor
  EXPECT_DOUBLE_EQ(pbr.baseColorFactor.at(3), 1.0);

  // Glossiness 1 everywhere: roughness 0, carried by the factor (the map holds 1 where the glossiness
  // is a factor). Specular 0.1 sits between plastic and metal: the prior keeps metalness low
  // (DESIGN.md: it rises from 0 at F0 0.04 to 1 at 0.45).
  float metalness_max = 0;
  if (pbr.metallicRoughnessTexture.index >= 0) {
    EXPECT_DOUBLE_EQ(pbr.roughnessFactor, 0.0);
    const Pixels mr = texture_pixels(converted, pbr.metallicRoughnessTexture.index);
    EXPECT_EQ(mr.width, source.width);
    for (int y = 0; y < mr.height; ++y)
      for (int x = 0; x < mr.width; ++x) {
        ASSERT_EQ(byte_at(mr, x, y, 1), 255) << x << "," << y;
        metalness_max = std::max(metalness_max, mr.at(x, y, 2));
      }
  } else {
    EXPECT_DOUBLE_EQ(pbr.roughnessFactor, 0.0);
    metalness_max = static_cast<float>(pbr.metallicFactor);
  }
  EXPECT_LT(metalness_max, 0.5f);

  // Against the solver, texel by texel: within what JPEG re-encoding costs. It rings at edges,
  // so the bounds are on the mean, the bias and the 99th percentile.
  const std::uint8_t s = to_byte(linear_to_srgb(0.1f));
  std::vector<int> diffs;
  double bias = 0;
  for (int y = 0; y < source.height; y += 3)
    for (int x = 0; x < source.width; x += 3) {
      const Texel d{byte_at(source, x, y, 0), byte_at(source, x, y, 1), byte_at(source, x, y, 2), 255};
      const Expected e = expected_texel(d, {s, s, s, 255});
      for (int c = 0; c < 3; ++c) {
        const int diff = byte_at(base, x, y, c) - e.base_color[static_cast<size_t>(c)];
        bias += diff;
        diffs.push_back(std::abs(diff));
      }
    }
  std::sort(diffs.begin(), diffs.end());
  double sum = 0;
  for (int d : diffs) sum += d;
  const double n = static_cast<double>(diffs.size());
  EXPECT_LT(sum / n, 1.5);
  EXPECT_LT(std::abs(bias / n), 0.5);
  EXPECT_LE(diffs[diffs.size() * 99 / 100], 20);
}

// The image data of a PNG: its IDAT chunks' data joined (PNG spec 10.1).
Bytes image_data(std::span<const std::uint8_t> png) {
  Bytes data;
  for (size_t at = 8; at + 12 <= png.size();) {
    const std::uint32_t length =
        std::uint32_t{png[at]} << 24 | std::uint32_t{png[at + 1]} << 16 | std::uint32_t{png[at + 2]} << 8 | png[at + 3];
    if (std::string(png.begin() + static_cast<std::ptrdiff_t>(at + 4),
                    png.begin() + static_cast<std::ptrdiff_t>(at + 8)) == "IDAT")
      data.insert(data.end(), png.begin() + static_cast<std::ptrdiff_t>(at + 8),
                  png.begin() + static_cast<std::ptrdiff_t>(at + 8 + length));
    at += 12 + length;
  }
  return data;
}

// What the conversion's bake makes of `legacy`'s factors over `diffuse` alone, every texel.
BakedTexels bake_diffuse_alone(const LegacyMaterial& legacy, const Pixels& diffuse) {
  BakeInputs inputs;
  inputs.diffuse_factor = legacy.diffuse_factor;
  inputs.specular_factor = legacy.specular_factor;
  inputs.glossiness_factor = legacy.glossiness_factor;
  inputs.diffuse = &diffuse;
  inputs.width = diffuse.width, inputs.height = diffuse.height;
  return bake(inputs, ConvertOptions().solver, 0);
}

// A palette PNG diffuse decodes to its palette's colours. Baked without a specular-glossiness
// texture, its base colour is its own file with the baked colours as the palette: the image data
// byte for byte (nothing re-encoded), each texel what the bake gives that texel's colour.
TEST(Textures, APaletteDiffuseBakesToItsOwnImageDataWithTheBakedColoursAsItsPalette) {
  ScratchDir scratch;
  for (const char* model : {"BoxTexturedNonPowerOfTwo", "Duck"}) {
    SCOPED_TRACE(model);
    const fs::path folder = assets_dir() / model / "specgloss";
    Asset asset = load_asset(folder / (std::string(model) + ".gltf"));
    const auto& png = asset.model.images.at(0);
    const auto bytes = read_file(folder / png.uri);
    ASSERT_TRUE(bytes);
    const std::optional<std::vector<std::uint32_t>> palette = png_palette(*bytes);
    ASSERT_TRUE(palette.has_value()) << "a palette PNG";

    const Pixels decoded = decode_image(*bytes, png.uri);
    EXPECT_TRUE(decoded.channels == 3 || decoded.channels == 4) << decoded.channels;
    EXPECT_EQ(decoded.bits, 8);
    std::set<std::uint32_t> colours;
    for (const std::uint32_t rgba : *palette) colours.insert(rgba & 0xFFFFFFu);
    for (int y = 0; y < decoded.height; ++y)
      for (int x = 0; x < decoded.width; ++x) {
        const std::uint32_t rgb = std::uint32_t{byte_at(decoded, x, y, 0)} |
                                  std::uint32_t{byte_at(decoded, x, y, 1)} << 8 |
                                  std::uint32_t{byte_at(decoded, x, y, 2)} << 16;
        ASSERT_TRUE(colours.count(rgb)) << x << "," << y << " is not a palette colour";
      }

    const LegacyMaterial legacy = read_legacy_material(asset, 0);
    ConversionReport report;
    const Asset converted = convert_save_reload(asset, scratch / "converted" / asset.path.filename(), &report);
    EXPECT_EQ(report.materials.at(0).outcome, MaterialOutcome::Metalness);
    EXPECT_TRUE(no_spec_gloss(converted));
    const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
    ASSERT_GE(pbr.baseColorTexture.index, 0);
    if (report.materials.at(0).outputs.base_color != TextureOutcome::Baked)
      continue;  // Duck's specular 0 reuses its diffuse
    const int image = converted.model.textures.at(static_cast<size_t>(pbr.baseColorTexture.index)).source;
    const auto written = encoded_image_bytes(converted, image);
    ASSERT_TRUE(png_palette(written).has_value());
    EXPECT_EQ(image_data(written), image_data(*bytes));
    EXPECT_LE(written.size(), bytes->size());
    const BakedTexels baked = bake_diffuse_alone(legacy, decoded);
    const Pixels base = decode_image(written, "the base colour");
    ASSERT_EQ(base.width, decoded.width);
    ASSERT_EQ(base.height, decoded.height);
    for (int y = 0; y < base.height; ++y)
      for (int x = 0; x < base.width; ++x)
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(
              byte_at(base, x, y, c),
              baked.base_color[(static_cast<size_t>(y) * static_cast<size_t>(base.width) + static_cast<size_t>(x)) *
                                   static_cast<size_t>(baked.base_channels) +
                               static_cast<size_t>(c)])
              << x << "," << y << " channel " << c;
  }
}

// 16-bit PNG input is not covered: no shared asset holds one, and the image module writes only
// 8-bit PNG (tests do not link OpenImageIO themselves).

// ---------------------------------------------------------------------------------------------
// Alpha and constants
// ---------------------------------------------------------------------------------------------

TEST(Textures, DiffuseAlphaBecomesBaseColorAlphaTexelForTexel) {
  ScratchDir scratch;
  constexpr int w = 9, h = 6;
  const Texels diffuse(w, h, 4, [](int x, int y) {
    return Texel{static_cast<std::uint8_t>(20 * x), 140, static_cast<std::uint8_t>(30 * y),
                 static_cast<std::uint8_t>(255 - 4 * (x + w * y))};
  });
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(diffuse, "diffuse")).factor("specularFactor", numbers({0.3, 0.3, 0.3}));
  Asset asset = built.save_and_load(scratch / "alpha.gltf");

  const Asset converted = convert_save_reload(asset, scratch / "converted" / asset.path.filename());
  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  ASSERT_GE(pbr.baseColorTexture.index, 0);
  const Pixels base = texture_pixels(converted, pbr.baseColorTexture.index);
  ASSERT_EQ(base.channels, 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) EXPECT_EQ(byte_at(base, x, y, 3), diffuse.at(x, y)[3]) << x << "," << y;
  EXPECT_DOUBLE_EQ(pbr.baseColorFactor.at(3), 1.0);
}

// The alpha a viewer sees: the texture's (1 when it has none) times the factor's.
double seen_alpha(const Pixels& base, int x, int y, const std::vector<double>& factor) {
  const double texel = base.channels == 2 || base.channels == 4 ? base.at(x, y, base.channels - 1) : 1.0;
  return texel * factor.at(3);
}

TEST(Textures, DiffuseAlphaFactorAppliesOnceWhetherAlphaVariesOrNot) {
  ScratchDir scratch;
  // Varying alpha (RGBA), and an opaque RGB diffuse whose only alpha is the factor's.
  for (const int channels : {4, 3}) {
    SCOPED_TRACE(channels);
    const Texels diffuse(4, 4, channels, [](int x, int y) {
      return Texel{static_cast<std::uint8_t>(40 * x), 60, static_cast<std::uint8_t>(50 * y),
                   static_cast<std::uint8_t>(60 + 10 * (x + 4 * y))};
    });
    SpecGlossModel built;
    built.diffuse_texture(built.add_png(diffuse, "diffuse"))
        .factor("diffuseFactor", numbers({1.0, 1.0, 1.0, 0.5}))
        .factor("specularFactor", numbers({0.3, 0.3, 0.3}));
    const fs::path folder = scratch / ("rgb" + std::string(channels == 4 ? "a" : ""));
    Asset asset = built.save_and_load(folder / "alpha-factor.gltf");

    const Asset converted = convert_save_reload(asset, folder / "converted" / "alpha-factor.gltf");
    const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
    ASSERT_GE(pbr.baseColorTexture.index, 0);
    const Pixels base = texture_pixels(converted, pbr.baseColorTexture.index);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x)
        EXPECT_NEAR(seen_alpha(base, x, y, pbr.baseColorFactor), 0.5 * diffuse.at(x, y)[3] / 255.0, 1.0 / 255)
            << x << "," << y;
  }
}

// The same with transparency (tRNS) and a diffuse alpha factor of 0.5: varying, the texture keeps
// each index's baked alpha; constant, the factor takes it and the palette is opaque. Either way a
// viewer sees each texel's alpha and colour as the bake made them, from the input's image data.
TEST(Textures, APaletteDiffuseWithTransparencyKeepsItsImageDataAndEveryTexelsAlpha) {
  ScratchDir scratch;
  for (const bool alpha_varies : {true, false}) {
    SCOPED_TRACE(alpha_varies ? "alpha varies" : "alpha constant");
    constexpr int w = 9, h = 6;
    const Texels diffuse(w, h, 4, [&](int x, int y) {  // six colours: a palette PNG with tRNS
      const int k = (x + y) % 6;
      return Texel{static_cast<std::uint8_t>(40 * k), static_cast<std::uint8_t>(200 - 30 * k), 90,
                   static_cast<std::uint8_t>(alpha_varies ? 60 + 30 * k : 128)};
    });
    SpecGlossModel built;
    built.diffuse_texture(built.add_png(diffuse, "diffuse"))
        .factor("diffuseFactor", numbers({1.0, 1.0, 1.0, 0.5}))
        .factor("specularFactor", numbers({0.3, 0.3, 0.3}));
    const fs::path folder = scratch / (alpha_varies ? "varies" : "constant");
    Asset asset = built.save_and_load(folder / "palette.gltf");
    const auto input = encoded_image_bytes(asset, 0);
    ASSERT_TRUE(png_palette(input).has_value());
    const Bytes input_bytes(input.begin(), input.end());
    const Pixels decoded = decode_image(input, "diffuse");
    const LegacyMaterial legacy = read_legacy_material(asset, 0);

    ConversionReport report;
    const Asset converted = convert_save_reload(asset, folder / "converted" / "palette.gltf", &report);
    ASSERT_EQ(report.materials.at(0).outputs.base_color, TextureOutcome::Baked);
    const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
    const int image = converted.model.textures.at(static_cast<size_t>(pbr.baseColorTexture.index)).source;
    const auto written = encoded_image_bytes(converted, image);
    EXPECT_EQ(image_data(written), image_data(input_bytes));

    const BakedTexels baked = bake_diffuse_alone(legacy, decoded);
    const Pixels base = decode_image(written, "the base colour");
    EXPECT_EQ(base.channels, alpha_varies ? 4 : 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t at = (static_cast<size_t>(y) * w + static_cast<size_t>(x)) * 4;
        for (int c = 0; c < 3; ++c)
          EXPECT_EQ(byte_at(base, x, y, c), baked.base_color[at + static_cast<size_t>(c)]) << x << "," << y;
        EXPECT_NEAR(seen_alpha(base, x, y, pbr.baseColorFactor), baked.base_color[at + 3] / 255.0, 1e-6)
            << x << "," << y;
        EXPECT_NEAR(seen_alpha(base, x, y, pbr.baseColorFactor), 0.5 * diffuse.at(x, y)[3] / 255.0, 1.0 / 255);
      }
  }
}

TEST(Textures, ConstantBakedTexturesBecomeFactorsAndNoImageIsWritten) {
  ScratchDir scratch;
  const Texel diffuse_texel{180, 90, 30, 255}, spec_gloss_texel{120, 120, 120, 200};
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(Texels(4, 4, 4, [&](int, int) { return diffuse_texel; }), "diffuse"))
      .spec_gloss_texture(built.add_png(Texels(4, 4, 4, [&](int, int) { return spec_gloss_texel; }), "specGloss"));
  Asset asset = built.save_and_load(scratch / "constant.gltf");

  ConversionReport report;
  const Asset converted = convert_save_reload(asset, scratch / "converted" / asset.path.filename(), &report);
  EXPECT_EQ(report.textures_baked, 0);
  EXPECT_EQ(report.images_removed, 2);
  EXPECT_TRUE(converted.model.images.empty());
  EXPECT_TRUE(converted.model.textures.empty());
  EXPECT_TRUE(converted.model.samplers.empty());
  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  EXPECT_EQ(pbr.baseColorTexture.index, -1);
  EXPECT_EQ(pbr.metallicRoughnessTexture.index, -1);

  const Expected e = expected_texel(diffuse_texel, spec_gloss_texel);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(pbr.baseColorFactor.at(static_cast<size_t>(c)), srgb8_to_linear(e.base_color[static_cast<size_t>(c)]),
                1e-6);
  EXPECT_NEAR(pbr.metallicFactor, e.metal_rough[2] / 255.0, 1e-9);
  EXPECT_NEAR(pbr.roughnessFactor, e.metal_rough[1] / 255.0, 1e-9);
  EXPECT_GT(pbr.metallicFactor, 0.0);
  // Only the .gltf was written: no image file beside it.
  EXPECT_EQ(files_under(scratch / "converted").size(), 1u);
}

TEST(Textures, ConstantDiffuseAtDielectricF0BecomesAFactorRatherThanAReusedTexture) {
  ScratchDir scratch;
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(Texels(3, 3, 3,
                                             [](int, int) {
                                               return Texel{150, 100, 50, 255};
                                             }),
                                      "diffuse"))
      .factor("specularFactor", numbers({0.04, 0.04, 0.04}));
  Asset asset = built.save_and_load(scratch / "constant-dielectric.gltf");

  ConversionReport report;
  const Asset converted = convert_save_reload(asset, scratch / "converted" / asset.path.filename(), &report);
  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  EXPECT_EQ(pbr.baseColorTexture.index, -1);
  EXPECT_TRUE(converted.model.images.empty());
  EXPECT_EQ(report.textures_reused, 0);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(pbr.baseColorFactor.at(static_cast<size_t>(c)),
                srgb8_to_linear(std::array<std::uint8_t, 3>{150, 100, 50}[static_cast<size_t>(c)]), 1e-6);
  EXPECT_DOUBLE_EQ(pbr.metallicFactor, 0.0);
}

TEST(Textures, DielectricDiffuseAtF0004ReusesTheDiffuseImageByteForByte) {
  ScratchDir scratch;
  constexpr int w = 6, h = 5;
  const Texels diffuse(w, h, 4, [](int x, int y) { return ramp_diffuse(x, y, w, h); });
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(diffuse, "diffuse"))
      .factor("specularFactor", numbers({0.04, 0.04, 0.04}))
      .factor("glossinessFactor", tinygltf::Value(0.7));
  Asset asset = built.save_and_load(scratch / "dielectric.gltf");
  const auto original = encoded_image_bytes(asset, 0);
  const Bytes original_bytes(original.begin(), original.end());
  const auto original_file = read_file(scratch / asset.model.images.at(0).uri);

  ConversionReport report;
  const Asset converted = convert_save_reload(asset, scratch / "converted" / asset.path.filename(), &report);
  EXPECT_EQ(report.textures_reused, 1);
  EXPECT_EQ(report.textures_baked, 0);  // no baseColor image, and a constant metallicRoughness
  ASSERT_EQ(converted.model.images.size(), 1u);
  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  ASSERT_GE(pbr.baseColorTexture.index, 0);
  const auto reused = encoded_image_bytes(
      converted, converted.model.textures.at(static_cast<size_t>(pbr.baseColorTexture.index)).source);
  EXPECT_EQ(Bytes(reused.begin(), reused.end()), original_bytes);
  EXPECT_EQ(read_file(scratch / "converted" / converted.model.images.at(0).uri), original_file);
  EXPECT_EQ(pbr.metallicRoughnessTexture.index, -1);
  EXPECT_DOUBLE_EQ(pbr.metallicFactor, 0.0);
  EXPECT_NEAR(pbr.roughnessFactor, 0.3, 1.0 / 255);
  for (double v : pbr.baseColorFactor) EXPECT_DOUBLE_EQ(v, 1.0);
}

// A 16-bit RGB PNG written by hand (PNG spec: IHDR bit depth 16, colour type 2; zlib stream of
// stored deflate blocks, RFC 1950/1951; CRC-32 per chunk), since the image module writes 8-bit only.
Bytes sixteen_bit_png(int width, int height, const std::function<std::array<std::uint16_t, 3>(int, int)>& texel) {
  auto crc32 = [](const Bytes& data, size_t from) {
    std::uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = from; i < data.size(); ++i) {
      crc ^= data[i];
      for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
  };
  auto put32 = [](Bytes& out, std::uint32_t v) {
    for (int k = 3; k >= 0; --k) out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  };
  Bytes png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  auto chunk = [&](const char* type, const Bytes& data) {
    put32(png, static_cast<std::uint32_t>(data.size()));
    const size_t start = png.size();
    png.insert(png.end(), type, type + 4);
    png.insert(png.end(), data.begin(), data.end());
    put32(png, crc32(png, start));
  };
  Bytes header;
  put32(header, static_cast<std::uint32_t>(width));
  put32(header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {16, 2, 0, 0, 0});
  Bytes raw;  // each row: filter byte 0, then big-endian 16-bit RGB
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    for (int x = 0; x < width; ++x)
      for (std::uint16_t v : texel(x, y))
        raw.insert(raw.end(), {static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v)});
  }
  EXPECT_LT(raw.size(), 65536u);  // one stored block
  Bytes zlib = {0x78,
                0x01,
                0x01,
                static_cast<std::uint8_t>(raw.size()),
                static_cast<std::uint8_t>(raw.size() >> 8),
                static_cast<std::uint8_t>(~raw.size()),
                static_cast<std::uint8_t>(~raw.size() >> 8)};
  zlib.insert(zlib.end(), raw.begin(), raw.end());
  std::uint32_t a = 1, b = 0;  // Adler-32
  for (std::uint8_t byte : raw) a = (a + byte) % 65521, b = (b + a) % 65521;
  put32(zlib, (b << 16) | a);
  chunk("IHDR", header);
  chunk("IDAT", zlib);
  chunk("IEND", {});
  return png;
}

TEST(Textures, SixteenBitPngDiffuseIsReadAtFullPrecision) {
  ScratchDir scratch;
  constexpr int w = 8, h = 4;
  // Values between 8-bit steps: an 8-bit reading would round them away.
  auto texel = [](int x, int y) {
    return std::array<std::uint16_t, 3>{static_cast<std::uint16_t>(20000 + 4099 * x + 77),
                                        static_cast<std::uint16_t>(9000 + 5003 * y + 129),
                                        static_cast<std::uint16_t>(40000 + 311 * (x + y))};
  };
  SpecGlossModel built;
  built.diffuse_texture(built.add_encoded(sixteen_bit_png(w, h, texel), "image/png", "diffuse16"))
      .factor("specularFactor", numbers({0.3, 0.3, 0.3}));
  Asset asset = built.save_and_load(scratch / "sixteen.gltf");
  const Pixels decoded = decode_image(encoded_image_bytes(asset, 0), "diffuse16");
  ASSERT_EQ(decoded.bits, 16);
  EXPECT_NEAR(decoded.at(3, 2, 0), texel(3, 2)[0] / 65535.0f, 1e-6f);

  const Asset converted = convert_save_reload(asset, scratch / "out" / "sixteen.gltf");
  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  ASSERT_GE(pbr.baseColorTexture.index, 0);
  const Pixels base = texture_pixels(converted, pbr.baseColorTexture.index);
  ASSERT_EQ(base.width, w);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::vec3 diffuse;
      for (int c = 0; c < 3; ++c) diffuse[c] = srgb_to_linear(texel(x, y)[static_cast<size_t>(c)] / 65535.0f);
      // The bake solves in SIMD lanes (solve_batch), which agrees with solve() to float rounding.
      const SpecGloss legacy{diffuse, glm::vec3(0.3f), 1.0f};
      MetalRough expected;
      solve_batch(std::span(&legacy, 1), std::span(&expected, 1));
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(byte_at(base, x, y, c), to_byte(linear_to_srgb(expected.base[c]))) << x << "," << y << " c" << c;
    }
}

// ---------------------------------------------------------------------------------------------
// Channels and mapping
// ---------------------------------------------------------------------------------------------

TEST(Textures, GlossinessZeroAndOneGiveRoughness255And0InGreenAndMetalnessInBlue) {
  ScratchDir scratch;
  const std::uint8_t plastic = 56;  // sRGB of F0 0.04
  const Texel iron{to_byte(linear_to_srgb(0.562f)), to_byte(linear_to_srgb(0.565f)), to_byte(linear_to_srgb(0.578f)),
                   0};
  // Columns: plastic on grey diffuse, iron on black diffuse. Rows: glossiness 0, then 1.
  const Texels diffuse(2, 2, 3, [](int x, int) { return x == 0 ? Texel{128, 128, 128, 255} : Texel{0, 0, 0, 255}; });
  const Texels spec_gloss(2, 2, 4, [&](int x, int y) {
    Texel t = x == 0 ? Texel{plastic, plastic, plastic, 0} : iron;
    t[3] = y == 0 ? 0 : 255;
    return t;
  });
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(diffuse, "diffuse")).spec_gloss_texture(built.add_png(spec_gloss, "specGloss"));
  Asset asset = built.save_and_load(scratch / "channels.gltf");

  const Asset converted = convert_save_reload(asset, scratch / "converted" / asset.path.filename());
  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  ASSERT_GE(pbr.metallicRoughnessTexture.index, 0);
  const Pixels mr = texture_pixels(converted, pbr.metallicRoughnessTexture.index);
  ASSERT_EQ(mr.width, 2);
  ASSERT_EQ(mr.height, 2);
  ASSERT_GE(mr.channels, 3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      SCOPED_TRACE(std::to_string(x) + "," + std::to_string(y));
      EXPECT_EQ(byte_at(mr, x, y, 0), 0);                 // R unused
      EXPECT_EQ(byte_at(mr, x, y, 1), y == 0 ? 255 : 0);  // G roughness = 1 - glossiness
      EXPECT_EQ(byte_at(mr, x, y, 2), x == 0 ? 0 : 255);  // B metalness: plastic 0, iron 1
    }
  EXPECT_DOUBLE_EQ(pbr.metallicFactor, 1.0);
  EXPECT_DOUBLE_EQ(pbr.roughnessFactor, 1.0);
  // Iron's baseColor is its F0, plastic's its diffuse.
  ASSERT_GE(pbr.baseColorTexture.index, 0);
  const Pixels base = texture_pixels(converted, pbr.baseColorTexture.index);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(byte_at(base, 0, 0, c), 128, 1);
    EXPECT_NEAR(byte_at(base, 1, 1, c), iron[static_cast<size_t>(c)], 1);
  }
}

tinygltf::Value::Object texture_transform(double rotation) {
  tinygltf::Value::Object transform;
  transform["offset"] = numbers({0.25, 0.5});
  transform["scale"] = numbers({2.5, 0.75});
  transform["rotation"] = tinygltf::Value(rotation);
  return transform;
}

TEST(Textures, SharedTextureTransformIsCopiedOntoBothBakedTextures) {
  ScratchDir scratch;
  constexpr int w = 8, h = 8;
  const Texels diffuse(w, h, 4, [](int x, int y) { return ramp_diffuse(x, y, w, h); });
  const Texels spec_gloss(w, h, 4, [](int x, int y) { return ramp_spec_gloss(x, y, w, h); });
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(diffuse, "diffuse"), texture_transform(0.3))
      .spec_gloss_texture(built.add_png(spec_gloss, "specGloss"), texture_transform(0.3));
  Asset asset = built.save_and_load(scratch / "transform.gltf");

  ConversionReport report;
  const Asset converted =
      convert_save_reload(asset, scratch / "converted" / asset.path.filename(), &report, every_metalness_value());
  ASSERT_EQ(report.materials.size(), 1u);
  EXPECT_EQ(report.materials[0].outcome, MaterialOutcome::Metalness);
  EXPECT_TRUE(no_spec_gloss(converted));
  const auto& pbr = converted.model.materials.at(0).pbrMetallicRoughness;
  ASSERT_GE(pbr.baseColorTexture.index, 0);
  ASSERT_GE(pbr.metallicRoughnessTexture.index, 0);
  const tinygltf::Value expected(texture_transform(0.3));
  for (const tinygltf::TextureInfo* info : {&pbr.baseColorTexture, &pbr.metallicRoughnessTexture}) {
    ASSERT_TRUE(info->extensions.count(kTextureTransform));
    EXPECT_TRUE(info->extensions.at(kTextureTransform) == expected);
    EXPECT_EQ(info->texCoord, 0);
  }
  EXPECT_NE(std::find(converted.model.extensionsUsed.begin(), converted.model.extensionsUsed.end(), kTextureTransform),
            converted.model.extensionsUsed.end());
  expect_baked(converted, diffuse, spec_gloss);  // baked in texture space, texel for texel
}

TEST(Textures, DifferentTextureTransformsLeaveTheMaterialLegacyUndecoded) {
  ScratchDir scratch;
  const Texels diffuse(4, 4, 4, [](int x, int y) { return ramp_diffuse(x, y, 4, 4); });
  const Texels spec_gloss(4, 4, 4, [](int x, int y) { return ramp_spec_gloss(x, y, 4, 4); });
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(diffuse, "diffuse"), texture_transform(0.3))
      .spec_gloss_texture(built.add_png(spec_gloss, "specGloss"), texture_transform(0.6));
  Asset asset = built.save_and_load(scratch / "transforms.gltf");

  const ConversionReport report = convert(asset);
  ASSERT_EQ(report.materials.size(), 1u);
  EXPECT_EQ(report.materials[0].outcome, MaterialOutcome::Legacy);
  EXPECT_EQ(report.images_decoded, 0);
  EXPECT_FALSE(report.warnings.empty());
  EXPECT_TRUE(asset.model.materials.at(0).extensions.count(kSpecGloss));
  EXPECT_EQ(asset.model.images.size(), 2u);
}

TEST(Textures, GlbInputKeepsBakedImagesInsideTheBinChunk) {
  ScratchDir scratch;
  constexpr int w = 5, h = 3;
  const Texels diffuse(w, h, 4, [](int x, int y) { return ramp_diffuse(x, y, w, h); });
  const Texels spec_gloss(w, h, 4, [](int x, int y) { return ramp_spec_gloss(x, y, w, h); });
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(diffuse, "diffuse")).spec_gloss_texture(built.add_png(spec_gloss, "specGloss"));
  Asset asset = built.save_and_load(scratch / "textured.glb");
  ASSERT_TRUE(asset.binary);
  for (const auto& image : asset.model.images) EXPECT_GE(image.bufferView, 0);

  const Asset converted =
      convert_save_reload(asset, scratch / "converted" / asset.path.filename(), nullptr, every_metalness_value());
  EXPECT_TRUE(converted.binary);
  EXPECT_EQ(files_under(scratch / "converted").size(), 1u);  // the .glb stands alone
  for (const auto& image : converted.model.images) {
    EXPECT_GE(image.bufferView, 0);
    EXPECT_TRUE(image.uri.empty());
  }
  expect_baked(converted, diffuse, spec_gloss);
}

// Pages of the mapping that starts at `start` which this process has touched (Rss in
// /proc/self/smaps, kB): a page the process never read is not counted, whatever the page cache holds.
long resident_kb_of_mapping(const void* start) {
  std::ifstream smaps("/proc/self/smaps");
  const auto wanted = reinterpret_cast<std::uintptr_t>(start);
  bool in_mapping = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t from = 0, to = 0;
    if (std::sscanf(line.c_str(), "%lx-%lx ", &from, &to) == 2) {  // a mapping's first line
      in_mapping = from == wanted;
    } else if (in_mapping && line.rfind("Rss:", 0) == 0) {
      return std::stol(line.substr(4));
    }
  }
  return -1;
}

// Image files are mapped, not read and copied on load: converting Avocado holds no page of the
// fallback maps it replaces or of the normal map it passes on, and gives back the pages of the two
// maps it decoded once it has their texels.
TEST(Textures, ConversionHoldsNoEncodedImagePagesOnceDone) {
  const fs::path gltf = assets_dir() / "Avocado/specgloss/Avocado.gltf";
  Asset asset = load_asset(gltf);
  for (const auto& image : asset.model.images) EXPECT_TRUE(image.image.empty()) << image.uri;
  auto resident_kb = [&](const char* uri) { return resident_kb_of_mapping(asset.image_files.at(uri)->bytes().data()); };
  {  // the measure sees a read when there is one
    const auto probe = asset.image_files.at("Avocado_normal.png")->bytes();
    EXPECT_NE(std::accumulate(probe.begin(), probe.end(), 0ull), 0ull);
    EXPECT_GT(resident_kb("Avocado_normal.png"), 0);
    asset.image_files.at("Avocado_normal.png")->release_pages();
  }
  const ConversionReport report = convert(asset);
  ASSERT_EQ(report.images_decoded, 2);
  for (const char* uri : {"Avocado_diffuse.png", "Avocado_specularGlossiness.png", "Avocado_baseColor.png",
                          "Avocado_roughnessMetallic.png", "Avocado_normal.png"})
    EXPECT_EQ(resident_kb(uri), 0) << uri;
  // What the mapping holds is the file, byte for byte.
  for (const auto& [uri, file] : asset.image_files) {
    const auto bytes = file->bytes();
    EXPECT_EQ(Bytes(bytes.begin(), bytes.end()), read_file(gltf.parent_path() / uri)) << uri;
  }
}

// The metallicRoughness map indexed straight from the bake's planes is the very file filter_png
// writes from the interleaved map, whatever the count (from 2) of (roughness, metalness) pairs up
// to 256, with a roughness plane or a roughness factor, and in whatever order the colours first
// appear (shuffled, not by value), also where half of them first appear past the 2^18 texels of
// filter_png's first scanned part. At 257 pairs there is no index (filter_png writes RGB).
TEST(Textures, AMetallicRoughnessMapIndexedFromItsPlanesIsTheFileFilterPngWrites) {
  std::mt19937 random(7);
  for (const auto& [width, height] : {std::pair{97, 61}, std::pair{640, 480}}) {
    for (const int pairs : {2, 37, 256, 257}) {  // one pair is a constant map: factors, no image
      for (const bool roughness_plane : {true, false}) {
        if (!roughness_plane && pairs > 256) continue;  // 256 metalness values at most
        SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + ", " + std::to_string(pairs) +
                     (roughness_plane ? " pairs" : " metalness values, roughness a factor"));
        BakedTexels t;
        t.width = width, t.height = height;  // odd sizes: rows of no particular length
        const std::size_t texels = static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
        t.first_roughness = 200;
        std::vector<std::pair<std::uint8_t, std::uint8_t>> colours;  // (roughness, metalness), all distinct
        for (int c = 0; c < pairs; ++c)
          colours.emplace_back(roughness_plane ? static_cast<std::uint8_t>(c / 16 * 15) : t.first_roughness,
                               static_cast<std::uint8_t>(roughness_plane ? c % 16 * 17 : c));
        std::shuffle(colours.begin(), colours.end(), random);
        // The first half of the colours from the start, in their shuffled order, then at random; the
        // other half from `late` on (past the first scanned part where the image has more).
        const std::size_t early = colours.size() - colours.size() / 2;
        const std::size_t late = texels > (std::size_t{1} << 18) ? (std::size_t{1} << 18) + 1000 : texels / 2;
        t.metalness.resize(texels);
        if (roughness_plane) t.roughness.resize(texels);
        for (std::size_t i = 0; i < texels; ++i) {
          const std::size_t c = i < early                           ? i
                                : i < late                          ? random() % early
                                : i - late < colours.size() - early ? early + (i - late)
                                                                    : random() % colours.size();
          t.metalness[i] = colours[c].second;
          if (roughness_plane) t.roughness[i] = colours[c].first;
        }
        const std::optional<BakedTexels::Indexed> indexed = t.metal_rough_indexed();
        const Bytes interleaved = encode_png(t.metal_rough(), t.width, t.height, 3, 1);
        if (pairs > 256) {
          EXPECT_FALSE(indexed.has_value());
          EXPECT_EQ(interleaved[25], 2);  // IHDR's colour type: RGB (3 is a palette)
          continue;
        }
        ASSERT_TRUE(indexed.has_value());
        EXPECT_EQ(indexed->palette.size(), static_cast<std::size_t>(pairs));
        const Bytes from_planes =
            deflate_png(filter_palette_png(indexed->indices, indexed->palette, t.width, t.height), 1);
        EXPECT_EQ(from_planes[25], 3);  // a palette image
        EXPECT_TRUE(from_planes == interleaved);
        const Pixels decoded = decode_image(from_planes, "the indexed map");
        EXPECT_TRUE(decoded.bytes == t.metal_rough());
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Metalness levels
// ---------------------------------------------------------------------------------------------

// Texels times the squared distance each moves.
double squared_move(const std::array<std::uint64_t, 256>& histogram, const std::array<std::uint8_t, 256>& to) {
  double sum = 0;
  for (size_t v = 0; v < 256; ++v)
    sum += static_cast<double>(histogram[v]) * std::pow(static_cast<double>(to[v]) - static_cast<double>(v), 2);
  return sum;
}

// The least squared move over every way to cut the held values (ascending) into `levels` runs, each
// run moved to its weighted mean rounded to a byte, or to 0 or 255 where it holds that end.
double least_squared_move(const std::array<std::uint64_t, 256>& histogram, int levels) {
  std::vector<int> values;
  for (int v = 0; v < 256; ++v)
    if (histogram[static_cast<size_t>(v)]) values.push_back(v);
  const int n = static_cast<int>(values.size());
  double best = std::numeric_limits<double>::infinity();
  // Each subset of the n - 1 gaps with levels - 1 cuts.
  for (std::uint32_t cuts = 0; cuts < (1u << (n - 1)); ++cuts) {
    if (std::popcount(cuts) != levels - 1) continue;
    double sum = 0;
    for (int first = 0; first < n;) {
      int last = first;
      while (last < n - 1 && !(cuts >> last & 1u)) ++last;
      double weight = 0, weighted = 0;
      for (int i = first; i <= last; ++i) {
        const auto count = static_cast<double>(histogram[static_cast<size_t>(values[static_cast<size_t>(i)])]);
        weight += count, weighted += count * values[static_cast<size_t>(i)];
      }
      const double level = values[static_cast<size_t>(first)] == 0    ? 0.0
                           : values[static_cast<size_t>(last)] == 255 ? 255.0
                                                                      : std::round(weighted / weight);
      for (int i = first; i <= last; ++i)
        sum += static_cast<double>(histogram[static_cast<size_t>(values[static_cast<size_t>(i)])]) *
               std::pow(values[static_cast<size_t>(i)] - level, 2);
      first = last + 1;
    }
    best = std::min(best, sum);
  }
  return best;
}

TEST(MetalnessLevels, AreTheLeastSquaredMoveOfAnySplitOfTheValuesWithPureDielectricAndMetalHeld) {
  std::mt19937 random(11);
  for (int trial = 0; trial < 300; ++trial) {
    std::array<std::uint64_t, 256> histogram{};
    const int held = 3 + static_cast<int>(random() % 8);
    for (int i = 0; i < held; ++i) histogram[random() % 256] = 1 + random() % 5000;
    if (trial % 3 == 0) histogram[0] = 1 + random() % 5000;    // pure dielectric texels
    if (trial % 4 == 0) histogram[255] = 1 + random() % 5000;  // pure metal texels
    const int distinct = static_cast<int>(std::count_if(histogram.begin(), histogram.end(), [](auto c) { return c; }));
    for (int levels = 2; levels <= 5; ++levels) {
      SCOPED_TRACE("trial " + std::to_string(trial) + ", " + std::to_string(levels) + " levels of " +
                   std::to_string(distinct));
      const std::array<std::uint8_t, 256> to = metalness_levels(histogram, levels);
      std::set<int> written;
      int last = -1;
      for (int v = 0; v < 256; ++v) {
        if (!histogram[static_cast<size_t>(v)]) {
          EXPECT_EQ(to[static_cast<size_t>(v)], v) << "a value no texel holds keeps itself";
          continue;
        }
        written.insert(to[static_cast<size_t>(v)]);
        EXPECT_GE(int{to[static_cast<size_t>(v)]}, last) << "the order of values is kept";
        last = to[static_cast<size_t>(v)];
      }
      if (histogram[0]) {
        EXPECT_EQ(to[0], 0);
      }
      if (histogram[255]) {
        EXPECT_EQ(to[255], 255);
      }
      if (distinct <= levels) {
        EXPECT_EQ(static_cast<int>(written.size()), distinct) << "nothing moves";
        EXPECT_EQ(squared_move(histogram, to), 0.0);
        continue;
      }
      EXPECT_LE(static_cast<int>(written.size()), levels);
      EXPECT_NEAR(squared_move(histogram, to), least_squared_move(histogram, levels),
                  1e-9 * least_squared_move(histogram, levels));
    }
  }
}

// Real assets whose metalness maps the solve fills with many values close together: written with
// fewer, the map takes fewer bytes, the base colour stays as solved (the same bytes), a texel of
// pure dielectric or pure metal keeps its value, roughness does not move, the report counts the
// values the files hold, and the error the report gives rises by at most the tolerance
// (CesiumMan's base colour is a JPEG, measured as written). Under a tolerance no level set meets,
// the map stays as solved.
TEST(MetalnessLevels, AMapWithFewerValuesIsSmallerWithinTheToleranceAndKeepsTheBaseColour) {
  ScratchDir scratch;
  for (const std::string model : {"BoxTextured", "BoxTexturedNonPowerOfTwo", "CesiumMan"}) {
    SCOPED_TRACE(model);
    const fs::path input = model_folder(model) / (model + ".gltf");
    ConversionReport every_report, fewer_report;
    Asset every_asset = load_asset(input), fewer_asset = load_asset(input);
    const Asset every =
        convert_save_reload(every_asset, scratch / model / "every.gltf", &every_report, every_metalness_value());
    const Asset fewer = convert_save_reload(fewer_asset, scratch / model / "fewer.gltf", &fewer_report);
    ASSERT_EQ(fewer_report.materials.size(), 1u);
    const MaterialReport &e = every_report.materials[0], &f = fewer_report.materials[0];
    EXPECT_FALSE(e.metalness_levels) << "not counted when every value is written";
    ASSERT_TRUE(f.metalness_levels);
    EXPECT_LT(f.metalness_levels->written, f.metalness_levels->solved);
    EXPECT_LE(f.metalness_levels->written, kMostMetalnessLevels);

    const auto& ep = every.model.materials[0].pbrMetallicRoughness;
    const auto& fp = fewer.model.materials[0].pbrMetallicRoughness;
    EXPECT_TRUE(texture_bytes(every, ep.baseColorTexture.index) == texture_bytes(fewer, fp.baseColorTexture.index));
    EXPECT_LT(texture_bytes(fewer, fp.metallicRoughnessTexture.index).size(),
              texture_bytes(every, ep.metallicRoughnessTexture.index).size());

    const Pixels every_map = texture_pixels(every, ep.metallicRoughnessTexture.index);
    const Pixels fewer_map = texture_pixels(fewer, fp.metallicRoughnessTexture.index);
    ASSERT_EQ(every_map.bytes.size(), fewer_map.bytes.size());
    std::set<int> every_values, fewer_values;
    for (size_t i = 2; i < every_map.bytes.size(); i += static_cast<size_t>(every_map.channels)) {
      every_values.insert(every_map.bytes[i]), fewer_values.insert(fewer_map.bytes[i]);
      if (every_map.bytes[i] == 0 || every_map.bytes[i] == 255) {
        EXPECT_EQ(fewer_map.bytes[i], every_map.bytes[i]);
      }
      EXPECT_EQ(fewer_map.bytes[i - 1], every_map.bytes[i - 1]) << "roughness is not moved";
    }
    EXPECT_EQ(static_cast<int>(every_values.size()), f.metalness_levels->solved);
    EXPECT_EQ(static_cast<int>(fewer_values.size()), f.metalness_levels->written);

    EXPECT_LE(
        judged_error(*f.error_a, ErrorModel::NormalIncidence) - judged_error(*e.error_a, ErrorModel::NormalIncidence),
        ConvertOptions().metalness_tolerance + 1e-9);

    // Under a tolerance of next to nothing, fewer values are written only where they do not raise
    // the error (some level sets lower it: the solve's continuity prior is not this figure);
    // otherwise the map is written as solved, byte for byte.
    ConvertOptions strict;
    strict.metalness_tolerance = 1e-9;
    ConversionReport strict_report;
    Asset strict_asset = load_asset(input);
    const Asset kept = convert_save_reload(strict_asset, scratch / model / "strict.gltf", &strict_report, strict);
    const MaterialReport& s = strict_report.materials[0];
    ASSERT_TRUE(s.metalness_levels);
    if (s.metalness_levels->written == s.metalness_levels->solved) {
      EXPECT_TRUE(texture_bytes(kept, kept.model.materials[0].pbrMetallicRoughness.metallicRoughnessTexture.index) ==
                  texture_bytes(every, ep.metallicRoughnessTexture.index));
    } else {
      EXPECT_LE(judged_error(*s.error_a, ErrorModel::NormalIncidence),
                judged_error(*e.error_a, ErrorModel::NormalIncidence) + 1e-9);
      EXPECT_GE(s.metalness_levels->written, f.metalness_levels->written) << "a tighter tolerance, no fewer levels";
    }
  }
}

// A map whose every texel the solve fits exactly (each a core material read back as spec-gloss,
// metalness rising across it): any value shared by two of its values costs error, so under a
// tolerance below that cost the map is written as solved, byte for byte, while a loose one takes
// two levels.
// One spec-gloss material whose w × h texels are the core materials core_at(x, y) read back as
// spec-gloss (to_spec_gloss), so that the solve can fit each texel exactly; saved at `path`.
template <class CoreAt>
Asset core_materials_as_spec_gloss(const fs::path& path, int w, int h, const CoreAt& core_at) {
  const auto srgb = [](float linear) { return to_byte(linear_to_srgb(linear)); };
  const Texels diffuse(w, h, 4, [&](int x, int y) {
    const glm::vec3 d = to_spec_gloss(core_at(x, y)).diffuse;
    return Texel{srgb(d.r), srgb(d.g), srgb(d.b), 255};
  });
  const Texels spec_gloss(w, h, 4, [&](int x, int y) {
    const SpecGloss l = to_spec_gloss(core_at(x, y));
    return Texel{srgb(l.specular.r), srgb(l.specular.g), srgb(l.specular.b), to_byte(l.glossiness)};
  });
  SpecGlossModel built;
  built.diffuse_texture(built.add_png(diffuse, "diffuse")).spec_gloss_texture(built.add_png(spec_gloss, "specGloss"));
  return built.save_and_load(path);
}

TEST(MetalnessLevels, AMapTheSolveFitsTexelByTexelIsKeptUnderATightTolerance) {
  ScratchDir scratch;
  constexpr int w = 24, h = 4;
  const Asset asset = core_materials_as_spec_gloss(scratch / "exact.gltf", w, h, [](int x, int y) {
    MetalRough core;
    core.base = glm::vec3(0.8f, 0.55f, 0.3f) * (0.7f + 0.1f * static_cast<float>(y));
    core.metalness = 0.15f + 0.7f * static_cast<float>(x) / (w - 1);
    core.roughness = 0.5f;
    return core;
  });

  const auto metal_rough_bytes = [&](const ConvertOptions& options, const std::string& name, ConversionReport& report) {
    Asset copy = load_asset(asset.path);
    const Asset converted = convert_save_reload(copy, scratch / name / "out.gltf", &report, options);
    return texture_bytes(converted, converted.model.materials[0].pbrMetallicRoughness.metallicRoughnessTexture.index);
  };
  ConversionReport every_report, tight_report, loose_report;
  const auto every = metal_rough_bytes(every_metalness_value(), "every", every_report);
  ConvertOptions tight, loose;
  tight.metalness_tolerance = 1e-6;
  loose.metalness_tolerance = 100;
  const auto kept = metal_rough_bytes(tight, "tight", tight_report);
  const auto fewest = metal_rough_bytes(loose, "loose", loose_report);
  ASSERT_TRUE(tight_report.materials[0].metalness_levels);
  EXPECT_GT(tight_report.materials[0].metalness_levels->solved, 16);
  EXPECT_EQ(tight_report.materials[0].metalness_levels->written, tight_report.materials[0].metalness_levels->solved);
  EXPECT_TRUE(kept == every);
  ASSERT_TRUE(loose_report.materials[0].metalness_levels);
  EXPECT_EQ(loose_report.materials[0].metalness_levels->written, 2);
  EXPECT_GT(judged_error(*loose_report.materials[0].error_a, ErrorModel::NormalIncidence),
            judged_error(*every_report.materials[0].error_a, ErrorModel::NormalIncidence));
  EXPECT_LT(fewest.size(), every.size());
}

// A map of three tight clusters of metalness (each core material read back as spec-gloss, so the
// solve fits it): two levels must merge two clusters, three only move values within theirs. Under
// a tolerance of half what two levels cost, the fewest levels within it are three, not the next
// power of two.
TEST(MetalnessLevels, TheFewestLevelsWithinTheToleranceAreWritten) {
  ScratchDir scratch;
  const Asset asset = core_materials_as_spec_gloss(scratch / "clusters.gltf", 27, 3, [](int x, int y) {
    MetalRough core;
    core.base = glm::vec3(0.7f, 0.5f, 0.35f) * (0.8f + 0.1f * static_cast<float>(y));
    core.metalness = 0.2f + 0.3f * static_cast<float>(x / 9) + 0.01f * static_cast<float>(x % 3 - 1);
    core.roughness = 0.5f;
    return core;
  });
  const auto converted = [&](const ConvertOptions& options, const std::string& name) {
    ConversionReport report;
    Asset copy = load_asset(asset.path);
    convert_save_reload(copy, scratch / name / "out.gltf", &report, options);
    return report.materials.at(0);
  };
  const auto judged = [](const MaterialReport& m) { return judged_error(*m.error_a, ErrorModel::NormalIncidence); };
  ConvertOptions loose;
  loose.metalness_tolerance = 100;
  const MaterialReport every = converted(every_metalness_value(), "every"), two = converted(loose, "two");
  ASSERT_TRUE(two.metalness_levels);
  ASSERT_GE(two.metalness_levels->solved, 6) << "the solve kept the clusters' spread";
  ASSERT_EQ(two.metalness_levels->written, 2);
  const double two_levels_cost = judged(two) - judged(every);
  ASSERT_GT(two_levels_cost, 0);

  ConvertOptions half;
  half.metalness_tolerance = two_levels_cost / 2;
  const MaterialReport fewest = converted(half, "half");
  ASSERT_TRUE(fewest.metalness_levels);
  EXPECT_EQ(fewest.metalness_levels->written, 3);
  EXPECT_LE(judged(fewest) - judged(every), half.metalness_tolerance + 1e-9);
}

// The bake's solve cache on inputs that overflow it: thousands of distinct colour pairs per band
// (slots taken by two queued inputs, answers known without a solve landing in claimed slots), and
// later bakes on the same pool threads, each of which keeps the cache of the one before it or
// starts a new generation (SolveContext): another specular factor (new), the same factors again
// (kept), a specularGlossiness map half of whose texels are new (kept), only the diffuse factor
// changed (new), then only the glossiness factor (kept under the normal-incidence model, which
// reads no glossiness; new under the appearance model). Every texel must hold its own input's
// answer, exactly as solve_batch gives it, and every error figure must be its stored texel's,
// under both error models: the appearance model's answer depends on the glossiness, so its cache
// is keyed on the glossiness byte too. A cache kept across a change that matters fails this.
TEST(BakeCache, EveryTexelGetsItsOwnSolveWhenTheCacheOverflowsAndAcrossBakes) {
  constexpr int w = 512, h = 64;
  std::uint32_t state = 12345;
  const auto next = [&] { return static_cast<std::uint8_t>((state = state * 1664525u + 1013904223u) >> 24); };
  Pixels diffuse, spec_gloss;
  diffuse.width = spec_gloss.width = w, diffuse.height = spec_gloss.height = h;
  diffuse.channels = 3, spec_gloss.channels = 4;
  for (int i = 0; i < w * h; ++i) {
    for (int c = 0; c < 3; ++c) diffuse.bytes.push_back(next());
    // A quarter of the texels full specular: times the factor 0.04 below, the core dielectric's F0.
    const bool full = next() < 64;
    for (int c = 0; c < 3; ++c) spec_gloss.bytes.push_back(full ? 255 : next());
    spec_gloss.bytes.push_back(next());
  }
  Pixels half_new = spec_gloss;  // the second half of its texels other colours
  for (size_t i = half_new.bytes.size() / 2; i < half_new.bytes.size(); ++i) half_new.bytes[i] = next();
  struct Bake {
    float specular_factor, diffuse_factor, glossiness_factor;
    const Pixels* spec_gloss;
  };
  const Bake bakes[] = {{0.04f, 1.0f, 1.0f, &spec_gloss}, {0.7f, 1.0f, 1.0f, &spec_gloss},
                        {0.7f, 1.0f, 1.0f, &spec_gloss},  {0.7f, 1.0f, 1.0f, &half_new},
                        {0.7f, 0.5f, 1.0f, &half_new},    {0.7f, 0.5f, 0.6f, &half_new}};
  for (const ErrorModel model : {ErrorModel::NormalIncidence, ErrorModel::Appearance})
    for (const Bake& made : bakes) {
      const bool appearance = model == ErrorModel::Appearance;
      const std::string what =
          "specular factor " + std::to_string(made.specular_factor) + ", diffuse factor " +
          std::to_string(made.diffuse_factor) + ", glossiness factor " + std::to_string(made.glossiness_factor) +
          (made.spec_gloss == &half_new ? ", half new" : "") + (appearance ? ", appearance" : ", normal incidence");
      const SolverSettings settings = solver_preset(SolverEffort::Balanced, model);
      BakeInputs in;
      in.diffuse = &diffuse, in.spec_gloss = made.spec_gloss;
      in.width = w, in.height = h;
      in.specular_factor = glm::vec3(made.specular_factor);
      in.diffuse_factor = glm::vec4(glm::vec3(made.diffuse_factor), 1.0f);
      in.glossiness_factor = made.glossiness_factor;
      const BakedTexels out = bake(in, settings, 0);
      const TexelBytes& sg = made.spec_gloss->bytes;
      std::vector<SpecGloss> legacy;
      for (int i = 0; i < w * h; ++i) {
        SpecGloss l;
        for (int c = 0; c < 3; ++c) {
          l.diffuse[c] = made.diffuse_factor * srgb8_to_linear(diffuse.bytes[static_cast<size_t>(i * 3 + c)]);
          l.specular[c] = made.specular_factor * srgb8_to_linear(sg[static_cast<size_t>(i * 4 + c)]);
        }
        // linear alpha, times the factor as the bake multiplies it
        l.glossiness = made.glossiness_factor * made.spec_gloss->value(static_cast<size_t>(i * 4 + 3));
        legacy.push_back(l);
      }
      std::vector<MetalRough> expected(legacy.size());
      solve_batch(legacy, expected, settings);
      int shortcuts = 0;
      for (size_t i = 0; i < legacy.size(); ++i) {
        const bool shortcut = solves_to_its_diffuse(legacy[i]);
        shortcuts += shortcut;
        const MetalRough e = shortcut ? MetalRough{legacy[i].diffuse, 0.0f, 0.0f} : expected[i];
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(out.base_color[i * 3 + static_cast<size_t>(c)], to_byte(linear_to_srgb(e.base[c])))
              << "texel " << i << " channel " << c << ", " << what;
        ASSERT_EQ(out.metalness[i], to_byte(e.metalness)) << "texel " << i << ", " << what;
      }
      EXPECT_EQ(shortcuts > 0, made.specular_factor == 0.04f) << what;
      // Every texel is a sample (0: all), and its error is taken through the cache's slots, or
      // apart for an answer held outside them: the figures must be those of each texel as stored.
      ErrorAccumulator a(legacy.size(), appearance), b(legacy.size());
      for (size_t i = 0; i < legacy.size(); ++i) {
        MetalRough stored;
        for (int c = 0; c < 3; ++c) stored.base[c] = srgb8_to_linear(out.base_color[i * 3 + static_cast<size_t>(c)]);
        stored.metalness = out.metalness[i] / 255.0f;
        stored.roughness = 1.0f - legacy[i].glossiness;
        a.set(i, legacy_reflectance(legacy[i], LegacyReading::A), core_reflectance(stored));
        if (appearance) a.set_appearance(i, appearance_delta_e(legacy_appearance(legacy[i]), core_appearance(stored)));
        b.set(i, legacy_reflectance(legacy[i], LegacyReading::B), core_reflectance(stored));
      }
      for (auto [baked, direct] : {std::pair{out.error_a, a}, std::pair{out.error_b, b}}) {
        const ReflectanceError got = baked.finish(), want = direct.finish();
        // The bake's ΔE2000 lanes are float, delta_e() is double: they agree to 1e-4 of the value.
        const auto close = [](double x, double y) { return std::abs(x - y) <= 1e-4 * std::max(1.0, std::abs(y)); };
        std::vector<std::pair<ErrorStats, ErrorStats>> figures = {{got.diffuse, want.diffuse}, {got.f0, want.f0}};
        ASSERT_EQ(got.appearance.has_value(), want.appearance.has_value()) << what;
        if (got.appearance) figures.emplace_back(*got.appearance, *want.appearance);
        for (const auto& [g, e] : figures)
          EXPECT_TRUE(close(g.mean, e.mean) && close(g.p95, e.p95) && close(g.max, e.max))
              << g.mean << " " << g.p95 << " " << g.max << " against " << e.mean << " " << e.p95 << " " << e.max << ", "
              << what;
      }
    }
}

// The bake may write base colour over a diffuse its caller hands over (BakeInputs::
// overwrite_diffuse): every texel, plane, flag and error figure must equal a bake into a new
// buffer, on a real asset and on constructed inputs (alpha with a factor; a diffuse that the base
// Small bakes are made several at once, one thread each, the largest first (convert.cpp prebake);
// each material's baked images must be the bytes, figures and place in the file that converting
// it alone gives, and the images must join the file in material order. Four materials with
// diffuse textures of 8², 64², 16² and 32² texels: the largest-first order is not theirs.
TEST(ConcurrentBakes, GiveEachMaterialWhatItsOwnConversionGivesInMaterialOrder) {
  ScratchDir scratch;
  const int sizes[] = {8, 64, 16, 32};
  SpecGlossModel built;
  std::vector<int> diffuse_textures;
  for (const int n : sizes)
    diffuse_textures.push_back(built.add_png(Texels(n, n, 3, [&](int x, int y) { return ramp_diffuse(x, y, n, n); }),
                                             "diffuse" + std::to_string(n)));
  built.diffuse_texture(diffuse_textures[0])
      .factor("specularFactor", numbers({0.3, 0.25, 0.2}))
      .factor("glossinessFactor", tinygltf::Value(0.6));
  const fs::path file = scratch / "four.gltf";
  const Asset one_material = built.save_and_load(file);
  // The same material four times, each on its own texture.
  const auto with_materials = [&](const std::vector<int>& which) {
    Asset asset = load_asset(file);
    const tinygltf::Material legacy = asset.model.materials.at(0);
    asset.model.materials.clear();
    for (const int k : which) {
      tinygltf::Material material = legacy;
      material.name = "material " + std::to_string(k);
      tinygltf::Value::Object extension = material.extensions.at(kSpecGloss).Get<tinygltf::Value::Object>();
      tinygltf::Value::Object info;
      info["index"] = tinygltf::Value(diffuse_textures[static_cast<size_t>(k)]);
      extension["diffuseTexture"] = tinygltf::Value(std::move(info));
      material.extensions[kSpecGloss] = tinygltf::Value(std::move(extension));
      asset.model.materials.push_back(std::move(material));
    }
    return asset;
  };
  Asset all = with_materials({0, 1, 2, 3});
  const ConversionReport together = convert(all);
  ASSERT_EQ(together.materials.size(), 4u);
  int last_image = -1;
  for (int k = 0; k < 4; ++k) {
    Asset alone = with_materials({k});
    const ConversionReport own = convert(alone);
    const auto& pbr = all.model.materials.at(static_cast<size_t>(k)).pbrMetallicRoughness;
    const auto& own_pbr = alone.model.materials.at(0).pbrMetallicRoughness;
    for (const auto& [texture, own_texture] :
         {std::pair{pbr.baseColorTexture.index, own_pbr.baseColorTexture.index},
          std::pair{pbr.metallicRoughnessTexture.index, own_pbr.metallicRoughnessTexture.index}}) {
      ASSERT_GE(texture, 0) << "material " << k;
      ASSERT_GE(own_texture, 0) << "material " << k;
      const int image = all.model.textures.at(static_cast<size_t>(texture)).source;
      EXPECT_EQ(
          all.model.images.at(static_cast<size_t>(image)).image,
          alone.model.images.at(static_cast<size_t>(alone.model.textures.at(static_cast<size_t>(own_texture)).source))
              .image)
          << "material " << k;
      EXPECT_GT(image, last_image) << "material " << k << ": its images join the file after the earlier materials'";
      last_image = image;
    }
    const MaterialReport &got = together.materials[static_cast<size_t>(k)], &want = own.materials.at(0);
    ASSERT_TRUE(got.error_a && want.error_a && got.error_b && want.error_b) << "material " << k;
    EXPECT_EQ(got.error_a->diffuse.mean, want.error_a->diffuse.mean) << "material " << k;
    EXPECT_EQ(got.error_a->f0.p95, want.error_a->f0.p95) << "material " << k;
    EXPECT_EQ(got.error_b->diffuse.max, want.error_b->diffuse.max) << "material " << k;
    EXPECT_EQ(got.outputs.base_color, TextureOutcome::Baked) << "material " << k;
  }
  EXPECT_EQ(together.textures_baked, 8);

  // A bake that fails is reported when its material's turn comes, as if made then: the first
  // failing material in order names the error, whichever bake failed first in time.
  Asset broken = with_materials({0, 1, 2, 3});
  for (const int k : {1, 3}) {
    const int image = broken.model.textures.at(static_cast<size_t>(diffuse_textures[static_cast<size_t>(k)])).source;
    tinygltf::Image& bad = broken.model.images.at(static_cast<size_t>(image));
    bad.uri.clear(), bad.as_is = true, bad.mimeType = "image/png";
    bad.image = Bytes(encode_png(std::vector<std::uint8_t>(3 * sizes[k] * sizes[k], 128), sizes[k], sizes[k], 3, 1));
    bad.image.resize(bad.image.size() / 2);  // cut in its image data: the header still reads
  }
  try {
    convert(broken);
    ADD_FAILURE() << "a broken texture was converted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer, pointer("images", broken.model.textures.at(static_cast<size_t>(diffuse_textures[1])).source))
        << e.what();
  }
}

// colour equals; a grey diffuse, whose layout differs from the base colour's and stays untouched).
TEST(BakeOverDiffuse, GivesTheSameBakeAsANewBuffer) {
  const fs::path avocado = assets_dir() / "Avocado/specgloss";
  auto decode_file = [](const fs::path& file) {
    const Bytes bytes = *read_file(file);
    return decode_image(bytes, file.string());
  };
  struct Case {
    std::string name;
    Pixels diffuse, spec_gloss;
    glm::vec4 diffuse_factor{1.0f};
    glm::vec3 specular_factor{1.0f};
    bool overwritten;
  };
  std::vector<Case> cases;
  cases.push_back({"Avocado", decode_file(avocado / "Avocado_diffuse.png"),
                   decode_file(avocado / "Avocado_specularGlossiness.png"), glm::vec4(1.0f), glm::vec3(1.0f), true});
  std::uint32_t state = 7;
  const auto next = [&] { return static_cast<std::uint8_t>((state = state * 1664525u + 1013904223u) >> 24); };
  auto random_pixels = [&](int channels, bool full_specular) {
    Pixels p;
    p.width = 97, p.height = 41, p.channels = channels;
    for (int i = 0; i < p.width * p.height * channels; ++i)
      p.bytes.push_back(full_specular && i % 4 != 3 ? 255 : next());
    return p;
  };
  cases.push_back({"RGBA diffuse, alpha factor 0.5", random_pixels(4, false), random_pixels(4, false),
                   glm::vec4(1.0f, 1.0f, 1.0f, 0.5f), glm::vec3(0.3f), true});
  cases.push_back({"diffuse over the core dielectric F0", random_pixels(3, false), random_pixels(4, true),
                   glm::vec4(1.0f), glm::vec3(0.04f), true});
  cases.push_back(
      {"grey diffuse", random_pixels(1, false), random_pixels(4, false), glm::vec4(1.0f), glm::vec3(0.5f), false});

  for (Case& c : cases) {
    SCOPED_TRACE(c.name);
    BakeInputs in;
    in.spec_gloss = &c.spec_gloss;
    in.width = c.diffuse.width, in.height = c.diffuse.height;
    in.diffuse_factor = c.diffuse_factor, in.specular_factor = c.specular_factor;
    in.diffuse = &c.diffuse;
    BakedTexels fresh = bake(in, SolverSettings{}, 4096);
    const TexelBytes diffuse_before = c.diffuse.bytes;
    in.overwrite_diffuse = &c.diffuse.bytes;
    BakedTexels over = bake(in, SolverSettings{}, 4096);

    EXPECT_EQ(c.diffuse.bytes.empty(), c.overwritten);  // handed over, or left as it was
    if (!c.overwritten) {
      EXPECT_TRUE(c.diffuse.bytes == diffuse_before);
    }
    EXPECT_TRUE(over.base_color == fresh.base_color);
    EXPECT_TRUE(over.metalness == fresh.metalness);
    EXPECT_TRUE(over.roughness == fresh.roughness);
    EXPECT_EQ(over.base_channels, fresh.base_channels);
    EXPECT_EQ(over.alpha, fresh.alpha);
    EXPECT_EQ(over.base_constant, fresh.base_constant);
    EXPECT_EQ(over.alpha_constant, fresh.alpha_constant);
    EXPECT_EQ(over.metal_rough_constant, fresh.metal_rough_constant);
    EXPECT_EQ(over.equals_diffuse, fresh.equals_diffuse);
    EXPECT_EQ(fresh.equals_diffuse, c.name == "diffuse over the core dielectric F0");
    const ReflectanceError a_over = over.error_a.finish(), a_fresh = fresh.error_a.finish();
    const ReflectanceError b_over = over.error_b.finish(), b_fresh = fresh.error_b.finish();
    for (const auto& [x, y] : {std::pair{a_over.diffuse, a_fresh.diffuse},
                               {a_over.f0, a_fresh.f0},
                               {b_over.diffuse, b_fresh.diffuse},
                               {b_over.f0, b_fresh.f0}}) {
      EXPECT_EQ(x.mean, y.mean);
      EXPECT_EQ(x.p95, y.p95);
      EXPECT_EQ(x.max, y.max);
    }
  }
}

}  // namespace
}  // namespace gltf_pbr
