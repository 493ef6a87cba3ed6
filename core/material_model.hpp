// The effective material: what any glTF material (core metal-rough, metal-rough with
// KHR_materials_specular / KHR_materials_ior, legacy KHR_materials_pbrSpecularGlossiness) reflects
// at normal incidence, from its factors and, texel by texel, its textures. The validators, the
// preview and the conversion error model share it, so every one of them reads a material the same way.
#pragma once
#include <array>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <map>
#include <string>

#include "core/asset.hpp"
#include "core/image.hpp"

namespace gltf_pbr {

enum class MaterialModel {
  MetalRough,  // glTF 2.0 core, optionally with KHR_materials_specular / KHR_materials_ior
  SpecGloss,   // archived KHR_materials_pbrSpecularGlossiness (it wins over the core fallback)
};

// The textures a material's reflectance reads. Colour textures are sRGB; the rest linear.
enum class TextureRole {
  BaseColor,           // sRGB RGB, linear A
  MetallicRoughness,   // linear, G roughness, B metalness
  Diffuse,             // legacy: sRGB RGB, linear A
  SpecularGlossiness,  // legacy: sRGB RGB specular, linear A glossiness
  Specular,            // KHR_materials_specular specularTexture: linear A
  SpecularColor,       // KHR_materials_specular specularColorTexture: sRGB RGB
};
constexpr int kTextureRoleCount = 6;
const char* texture_role_name(TextureRole role);  // "baseColorTexture", ...

struct MaterialTexture {
  tinygltf::TextureInfo info;  // as written: index, texCoord, extensions (KHR_texture_transform), extras
  int texture = -1;            // index into textures; -1: none
  int image = -1;              // textures[texture].source; -1 when the texture has no readable source
  int tex_coord = 0;
  bool transformed = false;  // KHR_texture_transform on the textureInfo
  std::string pointer;       // JSON pointer of the textureInfo
  bool present() const { return texture >= 0 && image >= 0; }
};

// Factors as written (defaults from the spec where absent) and the JSON pointers that name them.
struct MaterialInputs {
  int index = -1;
  std::string name;
  std::string pointer;  // "/materials/3"
  MaterialModel model = MaterialModel::MetalRough;

  // Core (glTF 2.0 section 5.19), defaults 1.
  glm::vec4 base_color{1.0f};
  float metallic = 1.0f, roughness = 1.0f;
  // KHR_materials_ior (default 1.5) and KHR_materials_specular (defaults 1).
  bool has_ior = false, has_specular = false;
  float ior = 1.5f;
  float specular = 1.0f;
  glm::vec3 specular_color{1.0f};
  // Legacy (archived extension), defaults 1.
  glm::vec4 diffuse{1.0f};
  glm::vec3 legacy_specular{1.0f};
  float glossiness = 1.0f;

  std::array<MaterialTexture, kTextureRoleCount> textures;
  // Pointer of each factor by its JSON name ("baseColorFactor", "specularFactor", ...): the factor
  // itself when written, else the object that would hold it (its default applies).
  std::map<std::string, std::string> factor_pointers;

  const MaterialTexture& texture(TextureRole role) const { return textures[static_cast<size_t>(role)]; }
  bool textured() const;
};

// The one reader of materials, in two strictnesses.
enum class MaterialReading {
  // For checks (validate, compare, the error model): never throws. Shapes the schema forbids
  // (wrong array lengths, non-numbers, non-finite numbers, a textureInfo without an integer index)
  // fall back to the spec default, since the structure step reports them.
  Tolerant,
  // For conversion, which writes what it reads: the same shapes in an extension object, and a
  // textureInfo naming a texture that does not exist or has no image, throw InputError naming the
  // file and the JSON pointer.
  Strict,
};
// Which model a viewer shades: the archived extension where the viewer reads it (validate, the
// legacy side), or the core material alone, as a viewer of converted output sees one that kept the
// extension (its fallback).
enum class SpecGlossReading { Read, Ignored };
MaterialInputs read_material_inputs(const tinygltf::Model& model, int index,
                                    SpecGlossReading spec_gloss = SpecGlossReading::Read);  // Tolerant
MaterialInputs read_material_inputs(const Asset& asset, int index, MaterialReading reading);

// Raw texel values as stored (RGBA in [0, 1]; absent textures read 1), one per role.
struct TexelInputs {
  std::array<glm::vec4, kTextureRoleCount> raw;
  TexelInputs() { raw.fill(glm::vec4(1.0f)); }
  glm::vec4& operator[](TextureRole role) { return raw[static_cast<size_t>(role)]; }
  const glm::vec4& operator[](TextureRole role) const { return raw[static_cast<size_t>(role)]; }
};

// What one point of a surface reflects, linear, under its own model.
struct SurfaceSample {
  glm::vec3 c_diff{0.0f};  // diffuse weight at normal incidence
  glm::vec3 f0{0.0f};      // specular reflectance at normal incidence
  float roughness = 1.0f;  // perceptual; alpha = roughness^2
  // Metal-rough: the stored metalness. Legacy: an estimate, smoothstep of mean F0 from 0.04
  // (plastic) to 0.45 (the darkest metal), the converter solver's prior (converter/solver.hpp).
  float metalness = 0.0f;
  // The end members that plausibility ranges speak of:
  glm::vec3 albedo{0.0f};         // diffuse colour of the dielectric part (base colour / legacy diffuse)
  glm::vec3 dielectric_f0{0.0f};  // F0 where the surface is dielectric
  glm::vec3 metal_f0{0.0f};       // F0 where the surface is metal (base colour / legacy specular)
  // The diffuse as the author stored it, before the model's own energy split: legacy diffuse
  // (the model darkens it by 1 - max(specular)); metal-rough c_diff (that model splits energy by
  // construction). stored_diffuse + F0 above 1 is light created.
  glm::vec3 stored_diffuse{0.0f};
};

// The reflectance at one point. Colour spaces: glTF 2.0 section 3.9.2 (baseColor sRGB, metallic-
// roughness linear), KHR_materials_specular (specularColorTexture sRGB, specularTexture A linear),
// archived KHR_materials_pbrSpecularGlossiness (diffuse and specular RGB sRGB, alpha linear).
// `core_only`: shade a metal-rough material as a viewer without KHR_materials_specular /
// KHR_materials_ior does (converter/evaluate.hpp's Viewer::CoreOnly).
SurfaceSample evaluate_surface(const MaterialInputs& material, const TexelInputs& texels, bool core_only = false);

// sRGB 8-bit code values decode through a table (the common case: decoded 8-bit images).
float srgb_texel_to_linear(float encoded);

// Channel values (RGBA; grey repeated, missing alpha 1) of texel (x, y).
glm::vec4 texel_rgba(const Pixels& pixels, int x, int y);

}  // namespace gltf_pbr
