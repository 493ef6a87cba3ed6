#include "converter/legacy_material.hpp"

#include <algorithm>
#include <glm/common.hpp>

#include "core/material_model.hpp"

namespace gltf_pbr {

LegacyMaterial read_legacy_material(const Asset& asset, int index) {
  // core/material_model is the one reader of materials; the conversion reads it strictly.
  const MaterialInputs in = read_material_inputs(asset, index, MaterialReading::Strict);
  LegacyMaterial legacy;
  // The extension's schema bounds every factor to [0, 1], and a file outside it still converts.
  // Alpha renders the same clamped (viewers clamp it before blending or the alpha cutoff), and a
  // negative reflectance means nothing, so both are read clamped, into a valid output. A diffuse
  // or specular above 1 (a measured gold's F0) goes to the solver, which brings it into gamut.
  legacy.diffuse_factor = glm::vec4(glm::max(glm::vec3(in.diffuse), 0.0f), std::clamp(in.diffuse.a, 0.0f, 1.0f));
  legacy.specular_factor = glm::max(in.legacy_specular, 0.0f);
  legacy.glossiness_factor = in.glossiness;
  if (const MaterialTexture& t = in.texture(TextureRole::Diffuse); t.present()) legacy.diffuse_texture = t.info;
  if (const MaterialTexture& t = in.texture(TextureRole::SpecularGlossiness); t.present())
    legacy.spec_gloss_texture = t.info;
  return legacy;
}

}  // namespace gltf_pbr
