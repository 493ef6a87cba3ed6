#include "converter/legacy_material.hpp"

#include "core/material_model.hpp"

namespace gltf_pbr {

LegacyMaterial read_legacy_material(const Asset& asset, int index) {
  // core/material_model is the one reader of materials; the conversion reads it strictly.
  const MaterialInputs in = read_material_inputs(asset, index, MaterialReading::Strict);
  LegacyMaterial legacy;
  legacy.diffuse_factor = in.diffuse;
  legacy.specular_factor = in.legacy_specular;
  legacy.glossiness_factor = in.glossiness;
  if (const MaterialTexture& t = in.texture(TextureRole::Diffuse); t.present()) legacy.diffuse_texture = t.info;
  if (const MaterialTexture& t = in.texture(TextureRole::SpecularGlossiness); t.present())
    legacy.spec_gloss_texture = t.info;
  return legacy;
}

}  // namespace gltf_pbr
