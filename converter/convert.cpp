#include "converter/convert.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <future>
#include <glm/vector_relational.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>

#include "converter/bake.hpp"
#include "converter/legacy_material.hpp"
#include "core/color.hpp"
#include "core/enum_names.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "core/image_header.hpp"
#include "core/parallel.hpp"

namespace gltf_pbr {
namespace {

constexpr const char* kSpecular = "KHR_materials_specular";
constexpr const char* kIor = "KHR_materials_ior";
constexpr const char* kTextureTransform = "KHR_texture_transform";

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

tinygltf::Value number_array_value(std::initializer_list<double> values) {
  tinygltf::Value::Array array;
  for (double v : values) array.emplace_back(v);
  return tinygltf::Value(std::move(array));
}

// Whether the two textures are sampled differently (texCoord set, KHR_texture_transform): such a
// material is left as spec-gloss, since one bake grid cannot hold both.
bool textures_mapped_apart(const LegacyMaterial& legacy) {
  if (!legacy.diffuse_texture || !legacy.spec_gloss_texture) return false;
  auto transform = [](const tinygltf::TextureInfo& info) {
    const auto it = info.extensions.find(kTextureTransform);
    return it == info.extensions.end() ? tinygltf::Value() : it->second;
  };
  const tinygltf::TextureInfo &a = *legacy.diffuse_texture, &b = *legacy.spec_gloss_texture;
  return a.texCoord != b.texCoord || transform(a) != transform(b);
}

class Converter {
 public:
  Converter(Asset& asset, const ConvertOptions& options) : asset_(asset), model_(asset.model), options_(options) {}

  ConversionReport run() {
    std::vector<std::pair<size_t, LegacyMaterial>> legacy_materials;
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      const auto extension = model_.materials[i].extensions.find(kSpecGloss);
      if (extension == model_.materials[i].extensions.end()) continue;
      legacy_materials.emplace_back(i, read_legacy_material(asset_, static_cast<int>(i)));
    }
    find_repeated_images(legacy_materials);
    for (const auto& [i, legacy] : legacy_materials)
      for (int image : images_of(legacy)) ++pending_uses_[image];
    prebake(legacy_materials);
    for (const auto& [i, legacy] : legacy_materials) {
      auto& material = model_.materials[i];
      MaterialReport entry;
      entry.index = static_cast<int>(i);
      entry.name = material.name;
      convert_material(material, legacy, entry);
      for (int image : images_of(legacy))
        if (--pending_uses_[image] == 0) decoded_.erase(image);  // its last reader is done
      if (entry.outcome != MaterialOutcome::Legacy) material.extensions.erase(kSpecGloss);
      report_.times += entry.times;
      report_.materials.push_back(std::move(entry));
    }
    update_extension_lists();
    // Pruning only follows a conversion: an asset with nothing to convert is left as it was.
    const PruneResult pruned = report_.materials.empty() ? PruneResult{} : prune_unused(asset_);
    report_.textures_removed = pruned.textures;
    report_.images_removed = pruned.images;
    report_.samplers_removed = pruned.samplers;
    report_.images_decoded = images_decoded_;
    report_.warnings.insert(report_.warnings.end(), asset_.warnings.begin(), asset_.warnings.end());
    return std::move(report_);
  }

 private:
  struct Bake {
    BakedTexels texels;
    ReflectanceError error_a, error_b;
    ReflectanceError extension_a, extension_b;  // the KHR_materials_specular route's (target specular)
    MetalRough factor_solution;                 // full precision, for factor-only materials
    bool reuse_diffuse = false;                 // baseColor texels equal the diffuse image's: keep its bytes
    // The diffuse image as it is, metallic 0: its JPEG base colour as baked and re-encoded measured
    // worse (keeps_diffuse_as_it_is). No image is written; `note` says why.
    bool dielectric_copy = false;
    std::string note;
    int base_color_image = -1, metal_rough_image = -1;
    // A map whose bytes equal an image an earlier bake wrote (materials whose diffuse factors differ
    // only in an alpha that the diffuse texture does not carry): that image serves it, shared.
    bool base_color_written_before = false, metal_rough_written_before = false;
    // The encoded maps until the material baked for adds them to the file (in material order,
    // whichever thread made them), and what making them cost it.
    Bytes base_color_bytes, metal_rough_bytes;
    bool base_color_jpeg = false, images_added = false;
    // The metalness map's distinct values as solved and as written (fewer_metalness_levels).
    std::optional<MetalnessLevels> metalness_levels;
    StageTimes times;
    int baked_for = -1;  // the material whose conversion baked it; later ones share its images
    // What a material using this bake gets in the slot whose image is `image`.
    TextureOutcome outcome(int image, bool written_before, int material) const {
      return image < 0                                  ? TextureOutcome::Factor
             : baked_for == material && !written_before ? TextureOutcome::Baked
                                                        : TextureOutcome::Shared;
    }
  };
  void convert_material(tinygltf::Material& material, const LegacyMaterial& legacy, MaterialReport& entry) {
    if (textures_mapped_apart(legacy)) {
      entry.outcome = MaterialOutcome::Legacy;
      entry.note =
          "diffuseTexture and specularGlossinessTexture use different texCoord sets or texture transforms; "
          "left as spec-gloss rather than baked wrongly";
      report_.warnings.push_back("material " + std::to_string(entry.index) + " (" + material.name + "): " + entry.note);
      return;
    }
    const Bake& baked = bake_for(legacy, entry);
    entry.texels = static_cast<long long>(baked.texels.width) * baked.texels.height;
    entry.error_samples = baked.texels.error_a.samples();
    entry.error_a = baked.error_a;
    entry.error_b = baked.error_b;

    auto& pbr = material.pbrMetallicRoughness;
    pbr = tinygltf::PbrMetallicRoughness();  // the author's old fallback is replaced
    if (options_.target == Target::Specular && route_copies_diffuse_validly(legacy) &&
        takes_specular_route(baked, entry)) {
      write_specular_route(material, legacy, baked, entry);
      return;
    }
    entry.outcome = MaterialOutcome::Metalness;
    if (baked.dielectric_copy) {
      pbr.baseColorTexture = *legacy.diffuse_texture;
      pbr.baseColorFactor = {legacy.diffuse_factor.r, legacy.diffuse_factor.g, legacy.diffuse_factor.b,
                             factor_alpha(legacy)};
      pbr.metallicFactor = 0.0;
      pbr.roughnessFactor = legacy.roughness_factor();
      ++report_.textures_reused;
      entry.outputs.base_color = TextureOutcome::InputReused;
      entry.outputs.metallic_roughness = TextureOutcome::Factor;
      entry.note = entry.note.empty() ? baked.note : entry.note + "; " + baked.note;
      return;
    }
    const BakedTexels& t = baked.texels;
    const tinygltf::TextureInfo* mapping = legacy.diffuse_texture      ? &*legacy.diffuse_texture
                                           : legacy.spec_gloss_texture ? &*legacy.spec_gloss_texture
                                                                       : nullptr;
    if (!mapping) {  // factors only, at full precision
      const MetalRough& f = baked.factor_solution;
      pbr.baseColorFactor = {f.base.r, f.base.g, f.base.b, factor_alpha(legacy)};
      pbr.metallicFactor = f.metalness;
      pbr.roughnessFactor = f.roughness;
      return;
    }
    // A texture that came out constant becomes a factor (even one equal to the diffuse image);
    // one equal to the diffuse image reuses it. An alpha the diffuse texture does not carry is the
    // factor's, as it is.
    const double alpha = t.base_channels == 3 ? factor_alpha(legacy) : t.alpha / 255.0;
    if (t.base_constant && t.alpha_constant) {
      pbr.baseColorFactor = {srgb8_to_linear(t.base_color[0]), srgb8_to_linear(t.base_color[1]),
                             srgb8_to_linear(t.base_color[2]), alpha};
      entry.outputs.base_color = TextureOutcome::Factor;
    } else if (baked.reuse_diffuse) {
      pbr.baseColorTexture = *legacy.diffuse_texture;
      pbr.baseColorFactor = {1.0, 1.0, 1.0, factor_alpha(legacy)};
      ++report_.textures_reused;
      entry.outputs.base_color = TextureOutcome::InputReused;
    } else {
      pbr.baseColorTexture = texture_for(baked.base_color_image, *mapping);
      pbr.baseColorFactor = {1.0, 1.0, 1.0, t.alpha_constant ? alpha : 1.0};
      entry.outputs.base_color = baked.outcome(baked.base_color_image, baked.base_color_written_before, entry.index);
    }
    // Where the glossiness is a factor, the map holds roughness 1 and the factor carries it (bake.hpp).
    const double roughness_factor = legacy.spec_gloss_texture ? 1.0 : legacy.roughness_factor();
    if (t.metal_rough_constant) {
      pbr.metallicFactor = t.metalness[0] / 255.0;
      pbr.roughnessFactor = roughness_factor * t.first_roughness / 255.0;
    } else {
      pbr.metallicRoughnessTexture = texture_for(baked.metal_rough_image, *mapping);
      pbr.roughnessFactor = roughness_factor;
      entry.metalness_levels = baked.metalness_levels;
    }
    entry.outputs.metallic_roughness =
        baked.outcome(baked.metal_rough_image, baked.metal_rough_written_before, entry.index);
  }

  // Target specular: whether a material takes the extension route, with the reason in its note.
  // Under the normal-incidence model, where the metalness fit's p95 ΔE2000 (the worse of diffuse
  // and F0, reading A) exceeds the tolerance: the route is exact there. Under the appearance model,
  // where the route lowers the appearance p95 by more than the tolerance: it is not exact in
  // appearance on rough surfaces (solver.hpp, specular_extension_appearance), so it must earn its place.
  bool takes_specular_route(const Bake& baked, MaterialReport& entry) const {
    auto figure = [](double x) {
      char text[32];
      std::snprintf(text, sizeof text, "%.2f", x);
      return std::string(text);
    };
    const std::string tolerance = figure(options_.specular_tolerance);
    if (options_.solver.error_model != ErrorModel::Appearance) {
      const double worst_p95 = std::max(baked.error_a.diffuse.p95, baked.error_a.f0.p95);
      if (worst_p95 <= options_.specular_tolerance) return false;
      entry.note = "metalness fit p95 " + figure(worst_p95) + " ΔE2000, above the tolerance " + tolerance;
      return true;
    }
    if (!baked.error_a.appearance || !baked.extension_a.appearance) return false;  // no sample: nothing to gain
    const double metalness = baked.error_a.appearance->p95, route = baked.extension_a.appearance->p95;
    const bool take = metalness - route > options_.specular_tolerance;
    entry.note =
        std::string(take ? "the specular extension lowers" : "metalness kept: the specular extension would take") +
        " the appearance p95 from " + figure(metalness) + " to " + figure(route) + " ΔE2000 (tolerance " + tolerance +
        ")";
    return take;
  }

  // Target specular, where the metalness fit misses: base = diffuse, metallic 0, and F0 carried
  // by KHR_materials_specular (exact at normal incidence under reading A in viewers that support it).
  void write_specular_route(tinygltf::Material& material, const LegacyMaterial& legacy, const Bake& baked,
                            MaterialReport& entry) {
    entry.outcome = MaterialOutcome::Specular;
    auto& pbr = material.pbrMetallicRoughness;
    pbr.baseColorFactor = {legacy.diffuse_factor.r, legacy.diffuse_factor.g, legacy.diffuse_factor.b,
                           factor_alpha(legacy)};
    if (legacy.diffuse_texture) {
      pbr.baseColorTexture = *legacy.diffuse_texture;
      entry.outputs.base_color = TextureOutcome::InputReused;
    }
    pbr.metallicFactor = 0.0;
    pbr.roughnessFactor = legacy.roughness_factor();
    tinygltf::Value::Object specular;
    specular["specularColorFactor"] =
        number_array_value({legacy.specular_factor.r, legacy.specular_factor.g, legacy.specular_factor.b});
    if (legacy.spec_gloss_texture) {
      tinygltf::Value::Object info;
      info["index"] = tinygltf::Value(legacy.spec_gloss_texture->index);
      if (legacy.spec_gloss_texture->texCoord) info["texCoord"] = tinygltf::Value(legacy.spec_gloss_texture->texCoord);
      if (!legacy.spec_gloss_texture->extensions.empty()) {
        tinygltf::Value::Object extensions(legacy.spec_gloss_texture->extensions.begin(),
                                           legacy.spec_gloss_texture->extensions.end());
        info["extensions"] = tinygltf::Value(std::move(extensions));
      }
      specular["specularColorTexture"] = tinygltf::Value(std::move(info));
      // Roughness comes from the glossiness in alpha: bake it (metalness stays 0).
      const Bake& rough = bake_roughness(legacy, entry.index);
      if (rough.texels.metal_rough_constant) {
        pbr.roughnessFactor = rough.texels.first_roughness / 255.0;
      } else {
        pbr.metallicRoughnessTexture = texture_for(rough.metal_rough_image, *legacy.spec_gloss_texture);
        pbr.roughnessFactor = 1.0;
      }
      entry.outputs.metallic_roughness =
          rough.outcome(rough.metal_rough_image, rough.metal_rough_written_before, entry.index);
    }
    material.extensions[kSpecular] = tinygltf::Value(std::move(specular));
    tinygltf::Value::Object ior;
    ior["ior"] = tinygltf::Value(static_cast<double>(kSpecularRouteIor));  // solver.hpp
    material.extensions[kIor] = tinygltf::Value(std::move(ior));
    // What was written is the extension route: report its error (F0 0.4% short of the legacy's at
    // normal incidence under reading A; reading B is what a full viewer with the appendix's (1 - F) shows).
    entry.error_samples = baked.texels.extension_a.samples();
    entry.error_a = baked.extension_a, entry.error_b = baked.extension_b;
  }

  // The inputs a bake depends on: identical ones give one output (DESIGN.md: no duplicate textures).
  // The glossiness factor of a diffuse texture without a specularGlossiness texture enters that
  // bake only through the appearance model's solve: the map holds roughness 1 and each material's
  // factor carries its own (a factor-only bake solves the roughness with the rest).
  std::string bake_key(const LegacyMaterial& legacy, bool roughness_only) const {
    const int diffuse_image = image_of(legacy.diffuse_texture), spec_image = image_of(legacy.spec_gloss_texture);
    const bool glossiness_bakes =
        !legacy.diffuse_texture || legacy.spec_gloss_texture || options_.solver.error_model == ErrorModel::Appearance;
    char key[256];
    std::snprintf(key, sizeof key, "%d|%d|%a,%a,%a,%a|%a,%a,%a|%a|%d", roughness_only ? -2 : diffuse_image, spec_image,
                  legacy.diffuse_factor.r, legacy.diffuse_factor.g, legacy.diffuse_factor.b, legacy.diffuse_factor.a,
                  legacy.specular_factor.r, legacy.specular_factor.g, legacy.specular_factor.b,
                  glossiness_bakes ? legacy.glossiness_factor : 0.0f, roughness_only);
    return key;
  }

  // Baking is shared: the first material with a bake's inputs adds its images to the file, the
  // later ones share them. A bake made ahead (prebake) is taken as it is, or its error rethrown.
  const Bake& bake_for(const LegacyMaterial& legacy, MaterialReport& entry, bool roughness_only = false) {
    const std::string key = bake_key(legacy, roughness_only);
    auto it = bakes_.find(key);
    if (it == bakes_.end()) {
      if (const auto failed = failed_bakes_.find(key); failed != failed_bakes_.end())
        std::rethrow_exception(failed->second);
      it = bakes_.emplace(key, make_bake(legacy, entry.index, roughness_only)).first;
    }
    Bake& bake = it->second;
    if (bake.baked_for != entry.index) {
      if (bake.base_color_image >= 0 || bake.metal_rough_image >= 0) ++report_.textures_shared;
      return bake;
    }
    if (!bake.images_added) {
      bake.images_added = true;
      entry.times += bake.times;
      if (!bake.base_color_bytes.empty())
        std::tie(bake.base_color_image, bake.base_color_written_before) =
            add_image(std::move(bake.base_color_bytes), "baseColor", bake.base_color_jpeg ? "image/jpeg" : "image/png");
      if (!bake.metal_rough_bytes.empty())
        std::tie(bake.metal_rough_image, bake.metal_rough_written_before) =
            add_image(std::move(bake.metal_rough_bytes), "metallicRoughness", "image/png");
      if (bake.base_color_written_before || bake.metal_rough_written_before) ++report_.textures_shared;
    }
    return bake;
  }

  // A bake of a legacy material's factors or texels for `material` (its error names it), with the
  // maps encoded but not yet in the file. Thread-safe: prebake() makes several at once.
  Bake make_bake(const LegacyMaterial& legacy, int material, bool roughness_only) {
    const int diffuse_image = image_of(legacy.diffuse_texture), spec_image = image_of(legacy.spec_gloss_texture);
    Bake bake;
    bake.baked_for = material;
    BakeInputs inputs = factor_inputs(legacy);
    inputs.measure_extension_route = options_.target == Target::Specular;
    if (!legacy.diffuse_texture && !legacy.spec_gloss_texture) {
      // Factors only: one solve at full precision, stored as factors (a single "texel").
      SpecGloss factors{glm::vec3(legacy.diffuse_factor), legacy.specular_factor, legacy.glossiness_factor};
      const auto start = Clock::now();
      bake.factor_solution = solve(factors, options_.solver);
      bake.texels.width = bake.texels.height = 1;
      const bool appearance = options_.solver.error_model == ErrorModel::Appearance;  // else null, as in the bake
      ErrorAccumulator a, b;
      const Reflectance converted = core_reflectance(bake.factor_solution);
      a.add(legacy_reflectance(factors, LegacyReading::A), converted);
      if (appearance) a.add(legacy_appearance(factors), core_appearance(bake.factor_solution));
      b.add(legacy_reflectance(factors, LegacyReading::B), converted);
      bake.texels.error_a = a, bake.texels.error_b = b;
      if (inputs.measure_extension_route) {
        const Reflectance route = specular_extension_reflectance(factors.diffuse, factors.specular);
        ErrorAccumulator route_a, route_b;
        route_a.add(legacy_reflectance(factors, LegacyReading::A), route);
        if (appearance) route_a.add(legacy_appearance(factors), specular_extension_appearance(factors));
        route_b.add(legacy_reflectance(factors, LegacyReading::B), route);
        bake.texels.extension_a = route_a, bake.texels.extension_b = route_b;
      }
      bake.times.solve_ms += ms_since(start);
    } else {
      auto start = Clock::now();
      // Asked before the decode, which gives the encoded pages back.
      const bool jpeg_diffuse =
          diffuse_image >= 0 && image_format_of(encoded_image_bytes(asset_, diffuse_image)) == ImageFormat::Jpeg;
      const bool diffuse_passes = diffuse_image >= 0 && passes_as_base_color(legacy, diffuse_image);
      // A palette diffuse baked alone may keep its image data (base_color_by_palette).
      const std::optional<std::vector<std::uint32_t>> diffuse_palette =
          diffuse_passes && !legacy.spec_gloss_texture && !roughness_only && !jpeg_diffuse
              ? png_palette(encoded_image_bytes(asset_, diffuse_image))
              : std::nullopt;
      // The two images decode concurrently (decoding is most of the pre-solve time).
      SharedPixels diffuse, spec_gloss;
      parallel_invoke([&] { spec_gloss = spec_image >= 0 ? decode(spec_image) : nullptr; },
                      [&] { diffuse = diffuse_image >= 0 && !roughness_only ? decode(diffuse_image) : nullptr; });
      const Pixels* const both[] = {diffuse.get(), spec_gloss.get()};
      const TexelGrid grid = bake_grid(both);
      inputs.width = grid.width;
      inputs.height = grid.height;
      const auto bake_pixels = static_cast<std::uint64_t>(inputs.width) * static_cast<std::uint64_t>(inputs.height);
      if (bake_pixels > max_image_pixels())
        throw InputError(asset_.path.string(), pointer("materials", material),
                         "its two textures bake at " + std::to_string(inputs.width) + "x" +
                             std::to_string(inputs.height) + ", above the limit of " +
                             std::to_string(max_image_pixels()) + " pixels (--max-image-pixels)");
      auto fit = [&](SharedPixels& pixels) {  // resampled only when the sizes differ
        if (pixels && (pixels->width != inputs.width || pixels->height != inputs.height))
          pixels = std::make_shared<Pixels>(resize(*pixels, inputs.width, inputs.height));
      };
      fit(diffuse);
      fit(spec_gloss);
      inputs.diffuse = diffuse.get();
      inputs.spec_gloss = spec_gloss.get();
      // A diffuse that no other reader holds gives its texels to the bake to write base colour over
      // (every Pixels here is made non-const, so the cast is sound).
      if (diffuse && diffuse.use_count() == 1)
        inputs.overwrite_diffuse = &std::const_pointer_cast<Pixels>(diffuse)->bytes;
      // A JPEG diffuse bakes to a JPEG base colour, which is lossy: its error is measured as
      // written (below), not by the bake.
      const bool error_as_written = jpeg_diffuse && !roughness_only;
      inputs.measure_as_written = error_as_written;
      const bool fewer_levels = !roughness_only && options_.metalness_tolerance > 0;
      inputs.keep_sampled_legacy = fewer_levels;
      bake.times.decode_ms += ms_since(start);

      start = Clock::now();
      bake.texels = gltf_pbr::bake(inputs, options_.solver, options_.max_error_samples);
      bake.reuse_diffuse = !roughness_only && diffuse && diffuse_passes &&
                           legacy.diffuse_factor == glm::vec4(glm::vec3(1.0f), legacy.diffuse_factor.a) &&
                           bake.texels.equals_diffuse;
      bake.times.solve_ms += ms_since(start);
      // The decoded inputs go before encoding (a later reader of the same image keeps its copy).
      const bool has_diffuse = diffuse != nullptr;
      inputs = {}, diffuse = nullptr, spec_gloss = nullptr;

      start = Clock::now();
      BakedTexels& t = bake.texels;
      // The metalness map's levels are chosen on the base colour as the file holds it, read at the
      // error samples: the bake's (taken here, and chosen beside the base colour's deflate), or a
      // JPEG's decode (below, once it is written; the diffuse may then be kept as it is instead,
      // with no metalness map: VC's 130 of 167).
      const auto choose_levels = [&](std::span<const std::uint8_t> base_at_samples) {
        bake.metalness_levels =
            fewer_metalness_levels(t, base_at_samples, options_.solver, options_.metalness_tolerance);
      };
      const bool levels_wait = fewer_levels && error_as_written;
      TexelBytes levels_base =
          fewer_levels && !levels_wait ? base_at_samples(t, t.base_color, t.base_channels) : TexelBytes();
      // Images are added in a fixed order afterwards.
      Bytes metal_rough, base_color;
      const bool jpeg_base = t.alpha_constant && has_diffuse && jpeg_diffuse;
      const bool bake_base = !roughness_only && !bake.reuse_diffuse && !(t.base_constant && t.alpha_constant);
      // A constant alpha goes into baseColorFactor, so the texture needs RGB only.
      TexelBytes rgb;
      if (bake_base && t.alpha_constant && t.base_channels == 4) {
        rgb.reserve(t.base_color.size() / 4 * 3);
        for (size_t i = 0; i < t.base_color.size(); i += 4)
          rgb.insert(rgb.end(), &t.base_color[i], &t.base_color[i + 3]);
      }
      const std::span<const std::uint8_t> base_texels =
          rgb.empty() ? std::span<const std::uint8_t>(t.base_color) : std::span<const std::uint8_t>(rgb);
      // A PNG base colour's rows are filtered first, on the whole pool; its deflate (one thread)
      // then runs beside the metalness levels' choice and the metallicRoughness map's encode. With
      // a map a thread from the start, the 4096² base colour's 50 MB were filtered on one core.
      std::optional<BakedPng> base_png;
      std::optional<Bytes> base_by_palette;
      if (bake_base && diffuse_palette)
        base_by_palette = base_color_by_palette(legacy, diffuse_image, *diffuse_palette, t.alpha_constant);
      if (base_by_palette) {
        base_color = std::move(*base_by_palette);
        keep_written(base_color, base_texels, {}, t.width, t.height, t.alpha_constant ? 3 : 4);
      } else if (bake_base && !jpeg_base) {
        // Given up: the RGB copy, or the bake's own texels unless their error is measured below.
        TexelBytes* const given = !rgb.empty() ? &rgb : !error_as_written ? &t.base_color : nullptr;
        base_png = filter_baked_png(base_texels, given, t.width, t.height, t.alpha_constant ? 3 : 4);
      }
      const auto encode_metal_rough = [&] {
        if (t.metal_rough_constant) return;
        // A map of at most 256 pairs is indexed from the planes; the preview, which keeps the
        // texels, and larger maps interleave them for filter_png.
        const std::optional<BakedTexels::Indexed> indexed =
            options_.keep_decoded ? std::nullopt : t.metal_rough_indexed();
        TexelBytes texels = indexed ? TexelBytes() : t.metal_rough();
        // The planes are read no more, unless the error is measured on the metalness below.
        if (!error_as_written) TexelBytes().swap(t.metalness), TexelBytes().swap(t.roughness);
        metal_rough = indexed ? deflate_png(filter_palette_png(indexed->indices, indexed->palette, t.width, t.height),
                                            options_.png_compression)
                              : deflate_baked_png(filter_baked_png(texels, &texels, t.width, t.height, 3));
      };
      parallel_invoke(
          [&] {
            if (levels_wait) return;
            if (fewer_levels) {
              choose_levels(levels_base);
              t.sampled_legacy = std::vector<SpecGloss>(), levels_base = TexelBytes();  // freed
            }
            encode_metal_rough();
          },
          [&] {
            // A lossy source stays lossy: a JPEG diffuse bakes to JPEG (PNG would be several times larger).
            if (base_png)
              base_color = deflate_baked_png(std::move(*base_png));
            else if (bake_base && jpeg_base)
              base_color = encode_jpeg(base_texels, t.width, t.height, 3, options_.jpeg_quality);
          });
      if (error_as_written) {
        // The report gives the error of the texels the file holds: a JPEG's decode (on VC the
        // encoding alone takes the diffuse mean from 0.2-0.6 to 0.7-4.4 ΔE2000), else the bake's
        // own (a factor, or an input image reused within one code of them). Timed with the encoding.
        std::shared_ptr<Pixels> written;
        if (bake_base && jpeg_base) {
          written = std::make_shared<Pixels>(decode_image(base_color, "the baked baseColor"));
          ++images_decoded_;
        }
        if (written && !legacy.spec_gloss_texture && diffuse_passes && keeps_diffuse_as_it_is(bake, *written)) {
          measure_dielectric_copy(t, options_.solver);
          if (options_.keep_decoded && !metal_rough.empty())  // the preview's copy of a map not written
            options_.keep_decoded->forget(image_content_key(metal_rough));
          Bytes().swap(base_color), Bytes().swap(metal_rough);
        } else {
          const std::span<const std::uint8_t> held = written ? written->bytes : t.base_color;
          const int channels = written ? written->channels : t.base_channels;
          measure_as_written(t, held, channels, options_.solver);
          if (levels_wait) {
            choose_levels(base_at_samples(t, held, channels));
            encode_metal_rough();
          }
          if (written && options_.keep_decoded)
            options_.keep_decoded->keep(image_content_key(base_color), std::move(written));
        }
        t.sampled_legacy = std::vector<SpecGloss>();  // freed (assigning {} would keep the capacity)
      }
      bake.base_color_bytes = std::move(base_color), bake.base_color_jpeg = jpeg_base;
      bake.metal_rough_bytes = std::move(metal_rough);
      bake.times.encode_ms += ms_since(start);
    }
    bake.error_a = bake.texels.error_a.finish();
    bake.error_b = bake.texels.error_b.finish();
    bake.extension_a = bake.texels.extension_a.finish();
    bake.extension_b = bake.texels.extension_b.finish();
    return bake;
  }

  // The diffuse factor's alpha as a baseColorFactor's: at most 1, which is what viewers make of a
  // larger one where no texture alpha multiplies it (the routes that copy a texture check that).
  static double factor_alpha(const LegacyMaterial& legacy) { return std::min(1.0, double{legacy.diffuse_factor.a}); }

  // Whether the diffuse factor is a valid baseColorFactor (glTF 2.0 schema: [0, 1]; the strict read
  // has made it non-negative), for the routes that copy it over the diffuse texture. The solver
  // brings a diffuse above 1 into gamut; a copy could not, nor undo an alpha above 1 that
  // multiplies the texture's.
  static bool diffuse_factor_is_a_base_color(const LegacyMaterial& legacy) {
    return glm::all(glm::lessThanEqual(legacy.diffuse_factor, glm::vec4(1.0f)));
  }

  // Whether the diffuse image may stand as the base colour with its bytes as they are: its header
  // reads without a problem (a CMYK JPEG is not one glTF allows), every image entry holding those
  // bytes declares the media type they have (materials that share a bake may each name another
  // entry), and its factor is a valid baseColorFactor. Else the material bakes.
  bool passes_as_base_color(const LegacyMaterial& legacy, int image) const {
    const std::span<const std::uint8_t> bytes = encoded_image_bytes(asset_, image);
    if (read_image_header(bytes, HeaderDepth::Size).problem != HeaderProblem::None ||
        !diffuse_factor_is_a_base_color(legacy))
      return false;
    const std::string mime = image_mime_of(bytes);
    for (size_t i = 0; i < model_.images.size(); ++i) {
      const auto same = first_with_same_bytes_.find(static_cast<int>(i));
      const int first = same == first_with_same_bytes_.end() ? static_cast<int>(i) : same->second;
      if (first == image && !model_.images[i].mimeType.empty() && model_.images[i].mimeType != mime) return false;
    }
    return true;
  }
  // The KHR_materials_specular route copies the diffuse factor and texture as they are.
  bool route_copies_diffuse_validly(const LegacyMaterial& legacy) const {
    return legacy.diffuse_texture ? passes_as_base_color(legacy, image_of(legacy.diffuse_texture))
                                  : diffuse_factor_is_a_base_color(legacy);
  }

  // A JPEG diffuse bakes to a JPEG base colour, and the re-encoding can cost more error than the
  // bake removes (VC, specular 0: diffuse means of 1.9-4.4 ΔE2000 as written, 0.3-0.7 for the
  // diffuse kept as it is). Where the diffuse image kept as it is, metallic 0, measures no worse
  // by the error model's own figure (judged_error) on kDecisionSamples of the error samples, the
  // material gets that, and no image is written. Only where the glossiness is a factor: a
  // specularGlossiness texture's roughness needs a map anyway.
  bool keeps_diffuse_as_it_is(Bake& bake, const Pixels& written) const {
    const WrittenAgainstCopy part =
        written_against_copy(bake.texels, written.bytes, written.channels, options_.solver, kDecisionSamples);
    const bool appearance = options_.solver.error_model == ErrorModel::Appearance;
    const double baked = judged_error(part.written, options_.solver.error_model),
                 copy = judged_error(part.copy, options_.solver.error_model);
    if (copy > baked) return false;
    char note[260];
    std::snprintf(note, sizeof note,
                  "the diffuse image kept as it is, metallic 0: %s %.2f ΔE2000, against %.2f for the base colour "
                  "as baked and re-encoded as JPEG (on %zu error samples)",
                  appearance ? "appearance mean" : "diffuse + F0 means", copy, baked, part.samples);
    bake.note = note;
    bake.dielectric_copy = true;
    return true;
  }

  // Small bakes, several at once, one thread each: inside a bake, each of the pool's threads
  // keeps its own cache of solves, and two solved a fifth of VC's inputs twice (509k solves
  // against 400k on one thread), while its JPEG encode and decode run on one thread anyway. The
  // first material of each bake adds its images in material order (bake_for), so the file is
  // the same whichever thread made them. Larger bakes keep the whole pool and are made in order,
  // so that their memory is not held twice.
  static constexpr std::int64_t kSmallBakeTexels = 1 << 20;
  void prebake(const std::vector<std::pair<size_t, LegacyMaterial>>& legacy_materials) {
    struct Job {
      std::string key;
      const LegacyMaterial* legacy;
      int material;
      std::int64_t texels;
    };
    std::vector<Job> jobs;
    std::set<std::string> keys;
    for (const auto& [i, legacy] : legacy_materials) {
      if (!legacy.diffuse_texture && !legacy.spec_gloss_texture) continue;  // factors: one solve
      if (textures_mapped_apart(legacy)) continue;                          // left as spec-gloss (convert_material)
      // A side is held to just above the bound (a header may claim 2^32 - 1 each way: its product
      // would overflow); an unreadable one counts as large.
      const auto side = [](std::int64_t v) { return v < 0 ? kSmallBakeTexels + 1 : std::min(v, kSmallBakeTexels + 1); };
      std::int64_t width = 1, height = 1;
      for (const int image : images_of(legacy)) {
        const ImageHeader header = read_image_header(encoded_image_bytes(asset_, image), HeaderDepth::Size);
        width = std::max(width, side(header.width));
        height = std::max(height, side(header.height));
      }
      if (width * height > kSmallBakeTexels) continue;
      std::string key = bake_key(legacy, false);
      if (keys.insert(key).second) jobs.push_back({std::move(key), &legacy, static_cast<int>(i), width * height});
    }
    if (jobs.size() < 2) return;
    // The largest first: the last bakes to finish are then small ones.
    std::stable_sort(jobs.begin(), jobs.end(), [](const Job& a, const Job& b) { return a.texels > b.texels; });
    // A decoded input that only these bakes read is given back once the last of them is made (run()
    // gives back the others as their last materials are converted), so the inputs of all the small
    // bakes are not held at once.
    std::map<int, int> unfinished_reads;  // image -> bakes yet to be made that read it
    for (const Job& job : jobs)
      for (const int image : images_of(*job.legacy)) ++unfinished_reads[image];
    std::set<int> read_later;  // by a larger bake, or by the specular route's roughness bake
    for (const auto& [i, legacy] : legacy_materials) {
      if (!keys.count(bake_key(legacy, false)))
        for (const int image : images_of(legacy)) read_later.insert(image);
      else if (options_.target == Target::Specular && legacy.spec_gloss_texture)
        read_later.insert(image_of(legacy.spec_gloss_texture));
    }
    std::vector<std::optional<Bake>> made(jobs.size());
    std::vector<std::exception_ptr> failed(jobs.size());
    // At most kTexelsAtOnce texels of bakes in the making (a 1 Mtexel bake holds ~30 MB while it is
    // made), however many cores there are.
    constexpr std::int64_t kTexelsAtOnce = 4 << 20;
    const std::int64_t at_once = std::max<std::int64_t>(1, kTexelsAtOnce / jobs.front().texels);  // the largest
    ThreadPool::shared().run(
        static_cast<std::int64_t>(jobs.size()),
        [&](std::int64_t j) {
          const Job& job = jobs[static_cast<size_t>(j)];
          try {
            made[static_cast<size_t>(j)] = make_bake(*job.legacy, job.material, false);
          } catch (...) {  // rethrown when its material is converted, as if made then
            failed[static_cast<size_t>(j)] = std::current_exception();
          }
          const std::lock_guard lock(decoded_mutex_);
          for (const int image : images_of(*job.legacy))
            if (--unfinished_reads[image] == 0 && !read_later.count(image)) decoded_.erase(image);
        },
        at_once);
    for (size_t j = 0; j < jobs.size(); ++j) {
      if (made[j])
        bakes_.emplace(jobs[j].key, std::move(*made[j]));
      else
        failed_bakes_.emplace(jobs[j].key, failed[j]);
    }
  }

  const Bake& bake_roughness(const LegacyMaterial& legacy, int material) {
    MaterialReport scratch;
    scratch.index = material;
    return bake_for(legacy, scratch, /*roughness_only=*/true);
  }

  using SharedPixels = std::shared_ptr<const Pixels>;

  // The images a legacy material's bake decodes, once per texture slot (one image in both slots is
  // two reads, decoded once through the cache below).
  std::vector<int> images_of(const LegacyMaterial& legacy) const {
    std::vector<int> images;
    for (const auto& texture : {legacy.diffuse_texture, legacy.spec_gloss_texture})
      if (texture) images.push_back(image_of(texture));
    return images;
  }
  // The image a texture slot reads, or -1 for an empty slot: the first of the images that hold the
  // same bytes.
  int image_of(const std::optional<tinygltf::TextureInfo>& texture) const {
    if (!texture) return -1;
    const int image = model_.textures[static_cast<size_t>(texture->index)].source;
    const auto same = first_with_same_bytes_.find(image);
    return same == first_with_same_bytes_.end() ? image : same->second;
  }
  // Image entries that hold the same bytes (exporters repeat an image per material) are one input,
  // decoded once and baked once (an error decoding it names the first). Only images of one encoded
  // size can be equal, so only those are hashed: a file without repeats hashes nothing.
  void find_repeated_images(const std::vector<std::pair<size_t, LegacyMaterial>>& legacy_materials) {
    std::map<size_t, std::set<int>> by_size;
    for (const auto& [i, legacy] : legacy_materials)
      for (const auto& texture : {legacy.diffuse_texture, legacy.spec_gloss_texture})
        if (texture) {
          const int image = model_.textures[static_cast<size_t>(texture->index)].source;
          by_size[encoded_image_bytes(asset_, image).size()].insert(image);
        }
    for (const auto& [size, images] : by_size) {
      if (size == 0 || images.size() < 2) continue;
      std::map<ImageContentKey, int> first;
      for (int image : images) {
        const int same = first.try_emplace(image_content_key(encoded_image_bytes(asset_, image)), image).first->second;
        if (same != image) first_with_same_bytes_[image] = same;
        release_encoded_image_pages(asset_, image);  // a repeat is never decoded, which would give them back
      }
    }
  }

  // Thread-safe (the two images of a bake decode concurrently). Each image decodes once: one read
  // more than once (by several materials, or in both slots of one) is kept until its last reader is
  // converted (run() drops it); one read once is not kept, so peak memory stays at one bake.
  // With keep_decoded, every image is also held there (for the preview) and is no longer the bake's
  // to write over; the key is taken before the decode gives the encoded pages back.
  SharedPixels decode(int image) {
    if (!options_.keep_decoded) return decode_once(image);
    const ImageContentKey key = image_content_key(encoded_image_bytes(asset_, image));
    if (SharedPixels held = options_.keep_decoded->find(key)) return held;
    SharedPixels pixels = decode_once(image);
    options_.keep_decoded->keep(key, pixels);
    return pixels;
  }

  SharedPixels decode_once(int image) {
    std::shared_future<SharedPixels> shared;
    std::promise<SharedPixels> promise;
    bool decode_here = true;
    {
      const std::lock_guard lock(decoded_mutex_);
      if (const auto it = decoded_.find(image); it != decoded_.end()) {
        shared = it->second;  // decoded (or being decoded) for an earlier read
        decode_here = false;
      } else if (pending_uses_[image] > 1) {
        shared = decoded_.emplace(image, promise.get_future().share()).first->second;
      }
    }
    if (!shared.valid()) return std::make_shared<Pixels>(decode_now(image));
    if (decode_here) {
      try {
        promise.set_value(std::make_shared<Pixels>(decode_now(image)));
      } catch (...) {
        promise.set_exception(std::current_exception());
      }
    }
    return shared.get();
  }

  Pixels decode_now(int image) {
    const auto bytes = encoded_image_bytes(asset_, image);
    const std::string name =
        pointer("images", image) + (model_.images[static_cast<size_t>(image)].uri.empty()
                                        ? ""
                                        : " (" + model_.images[static_cast<size_t>(image)].uri + ")");
    try {
      Pixels pixels = decode_image(bytes, name);
      release_encoded_image_pages(asset_, image);
      ++images_decoded_;  // this file's own count: the process-wide counter also sees other files' threads
      return pixels;
    } catch (const std::runtime_error& e) {
      throw InputError(asset_.path.string(), pointer("images", image), e.what());
    }
  }

  // The legacy factors as a bake's inputs, before its textures are given.
  static BakeInputs factor_inputs(const LegacyMaterial& legacy) {
    BakeInputs inputs;
    inputs.diffuse_factor = legacy.diffuse_factor;
    inputs.specular_factor = legacy.specular_factor;
    inputs.glossiness_factor = legacy.glossiness_factor;
    return inputs;
  }

  // The base colour of a palette PNG diffuse (`palette`, as png_palette reads it) baked without a
  // specular-glossiness texture: the bake's answer for a texel depends on the texel's values
  // alone, so each texel is its palette index's colour through the bake, and the diffuse's own
  // image data with the baked colours as its palette holds the same texels: nothing re-encoded
  // (BoxTexturedNonPowerOfTwo: 2,433 bytes where a re-encoding took 2,642). `opaque`: the alpha
  // goes into baseColorFactor (the texture's is 1). std::nullopt where the file's chunks do not
  // serve (png_with_palette).
  std::optional<Bytes> base_color_by_palette(const LegacyMaterial& legacy, int diffuse_image,
                                             const std::vector<std::uint32_t>& palette, bool opaque) {
    Pixels colours;  // the palette as a row of RGBA texels, as the PNG decoder gives them
    colours.width = static_cast<int>(palette.size()), colours.height = 1, colours.channels = 4;
    colours.bytes = TexelBytes(palette.size() * 4);
    for (size_t i = 0; i < palette.size(); ++i)
      for (size_t c = 0; c < 4; ++c) colours.bytes[i * 4 + c] = static_cast<std::uint8_t>(palette[i] >> (8 * c));
    BakeInputs inputs = factor_inputs(legacy);
    inputs.diffuse = &colours;
    inputs.width = colours.width, inputs.height = 1;
    const BakedTexels baked = gltf_pbr::bake(inputs, options_.solver, 1);
    std::vector<std::uint32_t> baked_palette(palette.size());
    for (size_t i = 0; i < palette.size(); ++i) {
      const std::uint8_t* texel = &baked.base_color[i * 4];
      baked_palette[i] = std::uint32_t{texel[0]} | std::uint32_t{texel[1]} << 8 | std::uint32_t{texel[2]} << 16 |
                         std::uint32_t{opaque ? std::uint8_t{255} : texel[3]} << 24;
    }
    return png_with_palette(encoded_image_bytes(asset_, diffuse_image), baked_palette);
  }

  // With keep_decoded (the preview), the texels a written map's bytes decode to, kept under their
  // key: `held` when given (moved in), else a copy of `texels`.
  void keep_written(const Bytes& written, std::span<const std::uint8_t> texels, TexelBytes&& held, int width,
                    int height, int channels) {
    if (!options_.keep_decoded) return;
    auto pixels = std::make_shared<Pixels>();
    pixels->width = width, pixels->height = height, pixels->channels = channels;
    pixels->bytes = !held.empty() ? std::move(held) : TexelBytes(texels.begin(), texels.end());
    options_.keep_decoded->keep(image_content_key(written), std::move(pixels));
  }

  // A baked map's PNG in encode_png's two steps (filter_png, deflate_png). `given`, when set, holds
  // `texels` and is read no more after this: the encoder frees it once filtered, or the preview
  // keeps it as the decoded image once the PNG is made (else it keeps a copy: PNG is lossless, so
  // these are the texels its bytes decode to), so a large map is not held twice while it compresses.
  struct BakedPng {
    FilteredPng rows;
    TexelBytes held;                       // for the preview: the texels given up, else empty and
    std::span<const std::uint8_t> texels;  // these are the caller's
    int width = 0, height = 0, channels = 0;
  };
  BakedPng filter_baked_png(std::span<const std::uint8_t> texels, TexelBytes* given, int width, int height,
                            int channels) {
    BakedPng png;
    if (!options_.keep_decoded) {
      png.rows =
          given ? filter_png(std::move(*given), width, height, channels) : filter_png(texels, width, height, channels);
      return png;
    }
    png.rows = filter_png(texels, width, height, channels);
    if (given) png.held = std::move(*given);  // `texels` stays valid: a moved buffer keeps its memory
    png.texels = texels, png.width = width, png.height = height, png.channels = channels;
    return png;
  }
  Bytes deflate_baked_png(BakedPng&& png) {
    Bytes bytes = deflate_png(std::move(png.rows), options_.png_compression);
    keep_written(bytes, png.texels, std::move(png.held), png.width, png.height, png.channels);
    return bytes;
  }

  // The image holding `encoded`, added to the file unless an earlier bake wrote the same bytes
  // (then true: no image is written twice).
  std::pair<int, bool> add_image(Bytes encoded, const std::string& role, const std::string& mime_type) {
    const auto [written, added] = images_written_.try_emplace(image_content_key(encoded), -1);
    if (!added) return {written->second, true};
    tinygltf::Image image;
    image.mimeType = mime_type;
    image.name = role + "_" + std::to_string(model_.images.size());
    image.image = std::move(encoded);
    image.as_is = true;
    model_.images.push_back(std::move(image));
    ++report_.textures_baked;
    written->second = static_cast<int>(model_.images.size()) - 1;
    return {written->second, false};
  }

  // A texture for a baked image, sampled like the input it came from (sampler, texCoord,
  // KHR_texture_transform), shared when several materials bake to the same image.
  tinygltf::TextureInfo texture_for(int image, const tinygltf::TextureInfo& mapping) {
    const int sampler = model_.textures[static_cast<size_t>(mapping.index)].sampler;
    const auto key = std::make_pair(image, sampler);
    auto it = textures_.find(key);
    if (it == textures_.end()) {
      tinygltf::Texture texture;
      texture.source = image;
      texture.sampler = sampler;
      model_.textures.push_back(texture);
      it = textures_.emplace(key, static_cast<int>(model_.textures.size()) - 1).first;
    }
    tinygltf::TextureInfo info = mapping;
    info.index = it->second;
    return info;
  }

  void update_extension_lists() {
    bool spec_gloss = false, specular = false;
    for (const auto& material : model_.materials) {
      spec_gloss = spec_gloss || material.extensions.count(kSpecGloss);
      specular = specular || material.extensions.count(kSpecular);
    }
    auto set = [](std::vector<std::string>& list, const std::string& name, bool present) {
      std::erase(list, name);
      if (present) list.push_back(name);
    };
    set(model_.extensionsUsed, kSpecGloss, spec_gloss);
    set(model_.extensionsRequired, kSpecGloss,
        spec_gloss && std::find(model_.extensionsRequired.begin(), model_.extensionsRequired.end(),
                                std::string(kSpecGloss)) != model_.extensionsRequired.end());
    if (specular) {
      set(model_.extensionsUsed, kSpecular, true);
      set(model_.extensionsUsed, kIor, true);
    }
  }

  Asset& asset_;
  tinygltf::Model& model_;
  const ConvertOptions& options_;
  ConversionReport report_;
  std::atomic<long> images_decoded_{0};  // decode() runs on several threads
  std::mutex decoded_mutex_;
  std::map<int, int> first_with_same_bytes_;  // image -> the first image of the same bytes (repeats only)
  std::map<int, int> pending_uses_;                          // image -> texture reads yet to convert
  std::map<int, std::shared_future<SharedPixels>> decoded_;  // images more than one of them reads
  std::map<std::string, Bake> bakes_;
  std::map<std::string, std::exception_ptr> failed_bakes_;  // prebake()'s, rethrown in material order
  std::map<std::pair<int, int>, int> textures_;
  std::map<ImageContentKey, int> images_written_;  // baked images by their bytes
};

}  // namespace

constexpr NameTable<MaterialOutcome, 3> kMaterialOutcomeNames{{{MaterialOutcome::Legacy, "legacy"},
                                                               {MaterialOutcome::Metalness, "metalness"},
                                                               {MaterialOutcome::Specular, "specular"}}};

const char* material_outcome_name(MaterialOutcome outcome) { return name_of(kMaterialOutcomeNames, outcome); }

constexpr NameTable<TextureOutcome, 5> kTextureOutcomeNames{{{TextureOutcome::None, "none"},
                                                             {TextureOutcome::Baked, "baked"},
                                                             {TextureOutcome::Shared, "shared"},
                                                             {TextureOutcome::InputReused, "inputReused"},
                                                             {TextureOutcome::Factor, "factor"}}};

const char* texture_outcome_name(TextureOutcome outcome) { return name_of(kTextureOutcomeNames, outcome); }

ConversionReport convert(Asset& asset, const ConvertOptions& options) {
  const auto before_used = asset.model.extensionsUsed;
  const auto before_required = asset.model.extensionsRequired;
  const auto start = Clock::now();
  ConversionReport report = Converter(asset, options).run();
  report.wall_ms = ms_since(start);
  // An extension listed but never used (BoxInterleaved) is dropped too: that is a change.
  report.extension_lists_changed =
      asset.model.extensionsUsed != before_used || asset.model.extensionsRequired != before_required;
  return report;
}

}  // namespace gltf_pbr
