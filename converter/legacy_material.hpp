// The legacy KHR_materials_pbrSpecularGlossiness material as the conversion uses it: factors and the
// textureInfos it carries over, read strictly through core/material_model.hpp.
#pragma once
#include <algorithm>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <optional>

#include "core/asset.hpp"

namespace gltf_pbr {

constexpr const char* kSpecGloss = "KHR_materials_pbrSpecularGlossiness";

struct LegacyMaterial {
  glm::vec4 diffuse_factor{1.0f};
  glm::vec3 specular_factor{1.0f};
  float glossiness_factor = 1.0f;
  std::optional<tinygltf::TextureInfo> diffuse_texture, spec_gloss_texture;
  // Core's roughness factor for this glossiness factor: alpha_legacy = (1 - g)^2 = alpha_core = r^2.
  double roughness_factor() const { return std::clamp(1.0 - glossiness_factor, 0.0, 1.0); }
};

// Reads and checks the extension object of material `index`, which has one. Throws InputError naming
// the JSON pointer for non-finite factors, wrong shapes, and textures or images that do not exist.
LegacyMaterial read_legacy_material(const Asset& asset, int index);

}  // namespace gltf_pbr
