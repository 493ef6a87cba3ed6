#include "converter/evaluate.hpp"

#include <array>
#include <vector>

#include "converter/bake.hpp"
#include "converter/legacy_material.hpp"
#include "core/error.hpp"
#include "core/material_model.hpp"

namespace gltf_pbr {
namespace {

// The decoded textures of one material, by role; null where it has none.
using RoleTextures = std::array<const Pixels*, kTextureRoleCount>;

RoleTextures decoded_textures(const MaterialInputs& material, const Asset& asset, DecodedImages& images) {
  RoleTextures out{};
  for (int role = 0; role < kTextureRoleCount; ++role) {
    const MaterialTexture& texture = material.textures[static_cast<size_t>(role)];
    if (texture.present()) out[static_cast<size_t>(role)] = &images.get(asset, texture.image);
  }
  return out;
}

// The reflectance of `material` at texel (x, y) of the common grid, under its own model
// (core/material_model.hpp).
Reflectance reflectance_at(const MaterialInputs& material, const RoleTextures& textures, int x, int y, bool core_only) {
  TexelInputs texels;
  for (int role = 0; role < kTextureRoleCount; ++role)
    if (const Pixels* pixels = textures[static_cast<size_t>(role)])
      texels.raw[static_cast<size_t>(role)] = texel_rgba(*pixels, x, y);
  const SurfaceSample surface = evaluate_surface(material, texels, core_only);
  return {surface.c_diff, surface.f0};
}

}  // namespace

std::vector<MaterialComparison> compare_conversion(const Asset& legacy, const Asset& converted, Viewer viewer,
                                                   size_t max_error_samples) {
  DecodedImages images;  // an image both assets hold decodes once
  std::vector<MaterialComparison> out;
  for (size_t i = 0; i < legacy.model.materials.size(); ++i) {
    const auto extension = legacy.model.materials[i].extensions.find(kSpecGloss);
    if (extension == legacy.model.materials[i].extensions.end()) continue;
    if (i >= converted.model.materials.size())
      throw InputError(converted.path.string(), pointer("materials", static_cast<int>(i)),
                       "material missing in the converted asset");
    // Strict, as convert reads it: non-finite or malformed legacy factors are refused, named.
    const MaterialInputs before = read_material_inputs(legacy, static_cast<int>(i), MaterialReading::Strict);
    // Neither viewer reads the archived extension: a material the conversion left as spec-gloss
    // shows its core fallback (white metal when it has none), which is the error a viewer sees.
    const MaterialInputs after = read_material_inputs(converted.model, static_cast<int>(i), SpecGlossReading::Ignored);
    RoleTextures before_textures = decoded_textures(before, legacy, images);
    RoleTextures after_textures = decoded_textures(after, converted, images);

    // The texels the bake reads and samples its error on (converter/bake.hpp): both materials'
    // textures on their common bake grid, resampled to it where their size differs, and every
    // stride-th texel in texel order. On our own output the figures are then the report's own.
    std::vector<const Pixels*> all;
    for (const RoleTextures* side : {&before_textures, &after_textures})
      for (const Pixels* pixels : *side) all.push_back(pixels);
    const TexelGrid grid = bake_grid(all);
    const auto texels = static_cast<std::uint64_t>(grid.width) * static_cast<std::uint64_t>(grid.height);
    if (texels > max_image_pixels())
      throw InputError(converted.path.string(), pointer("materials", static_cast<int>(i)),
                       "its textures and the original's meet at " + std::to_string(grid.width) + "x" +
                           std::to_string(grid.height) + ", above the limit of " + std::to_string(max_image_pixels()) +
                           " pixels (--max-image-pixels)");
    std::vector<Pixels> resampled;             // this material's, freed with it
    resampled.reserve(2 * kTextureRoleCount);  // stable addresses: the role arrays point into it
    for (RoleTextures* side : {&before_textures, &after_textures})
      for (const Pixels*& pixels : *side)
        if (pixels && (pixels->width != grid.width || pixels->height != grid.height))
          pixels = &resampled.emplace_back(resize(*pixels, grid.width, grid.height));

    const size_t stride = error_sample_stride(texels, max_error_samples);
    ErrorAccumulator error;
    for (size_t t = 0; t < texels; t += stride) {
      const int x = static_cast<int>(t % static_cast<size_t>(grid.width));
      const int y = static_cast<int>(t / static_cast<size_t>(grid.width));
      // The legacy side is reading A of solver.hpp, which is material_model's spec-gloss reading.
      error.add(reflectance_at(before, before_textures, x, y, false),
                reflectance_at(after, after_textures, x, y, viewer == Viewer::CoreOnly));
    }
    out.push_back({static_cast<int>(i), converted.model.materials[i].name, error.samples(), error.finish()});
  }
  return out;
}

}  // namespace gltf_pbr
