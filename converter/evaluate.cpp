#include "converter/evaluate.hpp"

#include <glm/vec2.hpp>

#include "converter/legacy_material.hpp"
#include "core/error.hpp"
#include "core/material_model.hpp"

namespace gltf_pbr {
namespace {

// The reflectance of `material` at uv under its own model (core/material_model.hpp), textures
// sampled at their nearest texel.
Reflectance reflectance_at(const MaterialInputs& material, const Asset& asset, DecodedImages& images, glm::vec2 uv,
                           bool core_only) {
  TexelInputs texels;
  for (int role = 0; role < kTextureRoleCount; ++role) {
    const MaterialTexture& texture = material.textures[static_cast<size_t>(role)];
    if (texture.present()) texels.raw[static_cast<size_t>(role)] = nearest_texel(images.get(asset, texture.image), uv);
  }
  const SurfaceSample surface = evaluate_surface(material, texels, core_only);
  return {surface.c_diff, surface.f0};
}

}  // namespace

std::vector<MaterialComparison> compare_conversion(const Asset& legacy, const Asset& converted, Viewer viewer,
                                                   int grid) {
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
    const MaterialInputs after = read_material_inputs(converted.model, static_cast<int>(i));
    const int n = before.textured() || after.textured() ? grid : 1;
    ErrorAccumulator error;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const glm::vec2 uv((static_cast<float>(x) + 0.5f) / static_cast<float>(n),
                           (static_cast<float>(y) + 0.5f) / static_cast<float>(n));
        // The legacy side is reading A of solver.hpp, which is material_model's spec-gloss reading.
        error.add(reflectance_at(before, legacy, images, uv, false),
                  reflectance_at(after, converted, images, uv, viewer == Viewer::CoreOnly));
      }
    out.push_back({static_cast<int>(i), converted.model.materials[i].name, error.samples(), error.finish()});
  }
  return out;
}

}  // namespace gltf_pbr
