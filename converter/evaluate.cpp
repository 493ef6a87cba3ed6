#include "converter/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/vec2.hpp>
#include <map>
#include <optional>

#include "converter/legacy_material.hpp"
#include "converter/solver.hpp"
#include "core/color.hpp"
#include "core/error.hpp"
#include "core/image.hpp"

namespace gltf_pbr {
namespace {

// Decoded images of one asset, decoded once each and only when a material samples them.
class TextureSampler {
 public:
  explicit TextureSampler(const Asset& asset) : asset_(asset) {}

  // Channel values (RGBA, missing alpha = 1, grey repeated) at uv, nearest texel, repeat wrap.
  glm::vec4 at(int texture, glm::vec2 uv) {
    const Pixels& p = image(texture);
    auto wrap = [](float t) { return t - std::floor(t); };
    const int x = std::min(p.width - 1, static_cast<int>(wrap(uv.x) * static_cast<float>(p.width)));
    const int y = std::min(p.height - 1, static_cast<int>(wrap(uv.y) * static_cast<float>(p.height)));
    glm::vec4 v(1.0f);
    for (int c = 0; c < 3; ++c) v[c] = p.at(x, y, p.channels >= 3 ? c : 0);
    if (p.channels == 2 || p.channels == 4) v.a = p.at(x, y, p.channels - 1);
    return v;
  }

 private:
  const Pixels& image(int texture) {
    const int source = asset_.model.textures.at(static_cast<size_t>(texture)).source;
    auto it = images_.find(source);
    if (it == images_.end())
      it = images_.emplace(source, decode_image(encoded_image_bytes(asset_.model, source), pointer("images", source)))
               .first;
    return it->second;
  }
  const Asset& asset_;
  std::map<int, Pixels> images_;
};

glm::vec3 srgb_rgb(glm::vec4 v) { return {srgb_to_linear(v.r), srgb_to_linear(v.g), srgb_to_linear(v.b)}; }

glm::vec3 vec3_of(const tinygltf::Value& value, glm::vec3 fallback) {
  if (!value.IsArray() || value.ArrayLen() < 3) return fallback;
  return {value.Get(0).GetNumberAsDouble(), value.Get(1).GetNumberAsDouble(), value.Get(2).GetNumberAsDouble()};
}

float number_of(const tinygltf::Value& value, float fallback) {
  return value.IsNumber() ? static_cast<float>(value.GetNumberAsDouble()) : fallback;
}

int texture_of(const tinygltf::Value& object, const char* key) {
  const tinygltf::Value& info = object.Get(key);
  return info.IsObject() && info.Get("index").IsInt() ? info.Get("index").GetNumberAsInt() : -1;
}

// The converted material's reflectance at uv, as `viewer` shades it (glTF 2.0 Appendix B; with
// KHR_materials_specular: dielectric F0 = min(F0(ior) * specularColor, 1) * specular, and the
// dielectric diffuse is scaled by 1 - max(dielectric F0) at normal incidence).
Reflectance converted_reflectance(const tinygltf::Material& material, TextureSampler& textures, glm::vec2 uv,
                                  Viewer viewer) {
  const auto& pbr = material.pbrMetallicRoughness;
  glm::vec3 base(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]);
  if (pbr.baseColorTexture.index >= 0) base *= srgb_rgb(textures.at(pbr.baseColorTexture.index, uv));
  float metalness = static_cast<float>(pbr.metallicFactor);
  if (pbr.metallicRoughnessTexture.index >= 0) metalness *= textures.at(pbr.metallicRoughnessTexture.index, uv).b;
  glm::vec3 dielectric_f0(0.04f);
  if (viewer == Viewer::Full) {
    float ior = 1.5f;
    if (auto it = material.extensions.find("KHR_materials_ior"); it != material.extensions.end())
      ior = number_of(it->second.Get("ior"), 1.5f);
    const float f0_from_ior = ((ior - 1.0f) / (ior + 1.0f)) * ((ior - 1.0f) / (ior + 1.0f));
    dielectric_f0 = glm::vec3(f0_from_ior);
    if (auto it = material.extensions.find("KHR_materials_specular"); it != material.extensions.end()) {
      const tinygltf::Value& s = it->second;
      glm::vec3 color = vec3_of(s.Get("specularColorFactor"), glm::vec3(1.0f));
      if (int t = texture_of(s, "specularColorTexture"); t >= 0) color *= srgb_rgb(textures.at(t, uv));
      float weight = number_of(s.Get("specularFactor"), 1.0f);
      if (int t = texture_of(s, "specularTexture"); t >= 0) weight *= textures.at(t, uv).a;
      dielectric_f0 = glm::min(dielectric_f0 * color, glm::vec3(1.0f)) * weight;
    }
  }
  const float max_f0 = std::max(dielectric_f0.r, std::max(dielectric_f0.g, dielectric_f0.b));
  return {base * (1.0f - metalness) * (1.0f - max_f0), glm::mix(dielectric_f0, base, metalness)};
}

}  // namespace

std::vector<MaterialComparison> compare_conversion(const Asset& legacy, const Asset& converted, Viewer viewer,
                                                   int grid) {
  TextureSampler legacy_textures(legacy), converted_textures(converted);
  std::vector<MaterialComparison> out;
  for (size_t i = 0; i < legacy.model.materials.size(); ++i) {
    const auto extension = legacy.model.materials[i].extensions.find(kSpecGloss);
    if (extension == legacy.model.materials[i].extensions.end()) continue;
    if (i >= converted.model.materials.size())
      throw InputError(converted.path.string(), pointer("materials", static_cast<int>(i)),
                       "material missing in the converted asset");
    const LegacyMaterial l = read_legacy_material(legacy, static_cast<int>(i), extension->second);
    const tinygltf::Material& c = converted.model.materials[i];
    const bool textured = l.diffuse_texture || l.spec_gloss_texture ||
                          c.pbrMetallicRoughness.baseColorTexture.index >= 0 ||
                          c.pbrMetallicRoughness.metallicRoughnessTexture.index >= 0;
    const int n = textured ? grid : 1;
    ErrorAccumulator error;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const glm::vec2 uv((static_cast<float>(x) + 0.5f) / static_cast<float>(n),
                           (static_cast<float>(y) + 0.5f) / static_cast<float>(n));
        SpecGloss s{glm::vec3(l.diffuse_factor), l.specular_factor, l.glossiness_factor};
        if (l.diffuse_texture) s.diffuse *= srgb_rgb(legacy_textures.at(l.diffuse_texture->index, uv));
        if (l.spec_gloss_texture) s.specular *= srgb_rgb(legacy_textures.at(l.spec_gloss_texture->index, uv));
        error.add(legacy_reflectance(s, LegacyReading::A), converted_reflectance(c, converted_textures, uv, viewer));
      }
    out.push_back({static_cast<int>(i), c.name, error.samples(), error.finish()});
  }
  return out;
}

}  // namespace gltf_pbr
