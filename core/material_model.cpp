#include "core/material_model.hpp"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>

#include "core/brdf.hpp"
#include "core/color.hpp"
#include "core/enum_names.hpp"
#include "core/error.hpp"
#include "core/json_pointer.hpp"

namespace gltf_pbr {
namespace {

constexpr const char* kSpecGlossExtension = "KHR_materials_pbrSpecularGlossiness";
constexpr const char* kSpecularExtension = "KHR_materials_specular";
constexpr const char* kIorExtension = "KHR_materials_ior";
constexpr const char* kTextureTransform = "KHR_texture_transform";

float max3(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }
float mean3(glm::vec3 v) { return (v.x + v.y + v.z) / 3.0f; }

// Reads a factor from an extension object; records its pointer (the factor when written, else the
// extension object, where its default applies). `strict_file`: the file to name when a present
// value has a shape the schema forbids (MaterialReading::Strict); null: the default applies.
class ExtensionReader {
 public:
  ExtensionReader(const tinygltf::Value& object, std::string pointer, MaterialInputs& out,
                  const std::string* strict_file)
      : object_(object), pointer_(std::move(pointer)), out_(out), strict_file_(strict_file) {
    if (!object_.IsObject()) refuse(pointer_, "the extension is not an object");
  }

  void number(const char* key, float* value) {
    const tinygltf::Value& v = object_.Get(key);
    const bool written = object_.IsObject() && object_.Has(key) && finite(v, pointer_ + "/" + key);
    if (written) *value = static_cast<float>(v.GetNumberAsDouble());
    out_.factor_pointers[key] = written ? pointer_ + "/" + key : pointer_;
  }
  void numbers(const char* key, float* values, int count) {
    const tinygltf::Value& v = object_.Get(key);
    const std::string where = pointer_ + "/" + key;
    bool written = object_.IsObject() && object_.Has(key);
    if (written && !(v.IsArray() && static_cast<int>(v.ArrayLen()) == count)) {
      refuse(where, "must be an array of " + std::to_string(count) + " numbers");
      written = false;
    }
    for (int i = 0; written && i < count; ++i) written = finite(v.Get(i), where + "/" + std::to_string(i));
    if (written)
      for (int i = 0; i < count; ++i) values[i] = static_cast<float>(v.Get(i).GetNumberAsDouble());
    out_.factor_pointers[key] = written ? where : pointer_;
  }
  void texture(const char* key, TextureRole role, const tinygltf::Model& model) {
    if (!object_.IsObject() || !object_.Has(key)) return;
    const tinygltf::Value& value = object_.Get(key);
    const std::string where = pointer_ + "/" + key;
    if (!value.IsObject() || !value.Get("index").IsInt()) return refuse(where, "textureInfo needs an integer index");
    MaterialTexture& t = out_.textures[static_cast<size_t>(role)];
    t.info.index = value.Get("index").GetNumberAsInt();
    t.info.texCoord = value.Get("texCoord").IsInt() ? value.Get("texCoord").GetNumberAsInt() : 0;
    if (value.Get("extensions").IsObject())
      for (const std::string& name : value.Get("extensions").Keys())
        t.info.extensions[name] = value.Get("extensions").Get(name);
    if (value.Get("extras").IsObject()) t.info.extras = value.Get("extras");
    read_texture_info(model, t.info, where, t);
    const std::string texture = "texture " + std::to_string(t.info.index);
    if (t.info.index < 0 || static_cast<size_t>(t.info.index) >= model.textures.size())
      refuse(where + "/index", texture + " does not exist");
    else if (t.image < 0)
      refuse(where + "/index", texture + " has no image this tool can read");
  }

  // The textureInfo fields every reader keeps, and the image its texture names (-1: none).
  static void read_texture_info(const tinygltf::Model& model, const tinygltf::TextureInfo& info, std::string pointer,
                                MaterialTexture& out) {
    if (info.index < 0) return;
    if (&out.info != &info) out.info = info;
    out.texture = info.index;
    out.tex_coord = info.texCoord;
    out.transformed = info.extensions.contains(kTextureTransform);
    out.pointer = std::move(pointer);
    if (static_cast<size_t>(info.index) < model.textures.size()) {
      const int source = model.textures[static_cast<size_t>(info.index)].source;
      if (source >= 0 && static_cast<size_t>(source) < model.images.size()) out.image = source;
    }
  }

 private:
  // Strict: throws. Tolerant: the caller falls back to the default.
  void refuse(const std::string& where, const std::string& why) const {
    if (strict_file_) throw InputError(*strict_file_, where, why);
  }
  bool finite(const tinygltf::Value& value, const std::string& where) const {
    if (!value.IsNumber()) return refuse(where, "not a number"), false;
    const double v = value.GetNumberAsDouble();
    if (!std::isfinite(v)) return refuse(where, "is " + std::to_string(v) + "; factors must be finite"), false;
    return true;
  }

  const tinygltf::Value& object_;
  std::string pointer_;
  MaterialInputs& out_;
  const std::string* strict_file_;
};

}  // namespace

constexpr NameTable<TextureRole, 6> kTextureRoleNames{{{TextureRole::BaseColor, "baseColorTexture"},
                                                       {TextureRole::MetallicRoughness, "metallicRoughnessTexture"},
                                                       {TextureRole::Diffuse, "diffuseTexture"},
                                                       {TextureRole::SpecularGlossiness, "specularGlossinessTexture"},
                                                       {TextureRole::Specular, "specularTexture"},
                                                       {TextureRole::SpecularColor, "specularColorTexture"}}};

const char* texture_role_name(TextureRole role) { return name_of(kTextureRoleNames, role); }

bool MaterialInputs::textured() const {
  return std::any_of(textures.begin(), textures.end(), [](const MaterialTexture& t) { return t.present(); });
}

namespace {

MaterialInputs read_inputs(const tinygltf::Model& model, int index, const std::string* strict_file,
                           SpecGlossReading spec_gloss = SpecGlossReading::Read) {
  const tinygltf::Material& material = model.materials.at(static_cast<size_t>(index));
  MaterialInputs in;
  in.index = index;
  in.name = material.name;
  in.pointer = pointer("materials", index);

  // Core factors: tinygltf keeps no presence flag, so a factor that differs from its default was
  // written; one that equals it is named by its parent object.
  const auto& pbr = material.pbrMetallicRoughness;
  const std::string pbr_pointer = in.pointer + "/pbrMetallicRoughness";
  if (pbr.baseColorFactor.size() == 4)
    for (int c = 0; c < 4; ++c) in.base_color[c] = static_cast<float>(pbr.baseColorFactor[static_cast<size_t>(c)]);
  in.metallic = static_cast<float>(pbr.metallicFactor);
  in.roughness = static_cast<float>(pbr.roughnessFactor);
  if (!std::isfinite(in.metallic)) in.metallic = 1.0f;
  if (!std::isfinite(in.roughness)) in.roughness = 1.0f;
  for (int c = 0; c < 4; ++c)
    if (!std::isfinite(in.base_color[c])) in.base_color[c] = 1.0f;
  in.factor_pointers["baseColorFactor"] =
      in.base_color == glm::vec4(1.0f) ? pbr_pointer : pbr_pointer + "/baseColorFactor";
  in.factor_pointers["metallicFactor"] = in.metallic == 1.0f ? pbr_pointer : pbr_pointer + "/metallicFactor";
  in.factor_pointers["roughnessFactor"] = in.roughness == 1.0f ? pbr_pointer : pbr_pointer + "/roughnessFactor";
  ExtensionReader::read_texture_info(model, pbr.baseColorTexture, pbr_pointer + "/baseColorTexture",
                                     in.textures[static_cast<size_t>(TextureRole::BaseColor)]);
  ExtensionReader::read_texture_info(model, pbr.metallicRoughnessTexture, pbr_pointer + "/metallicRoughnessTexture",
                                     in.textures[static_cast<size_t>(TextureRole::MetallicRoughness)]);

  const std::string extensions_pointer = in.pointer + "/extensions/";
  if (auto it = material.extensions.find(kSpecGlossExtension);
      it != material.extensions.end() && spec_gloss == SpecGlossReading::Read) {
    // The archived extension replaces the core model in the viewers that support it; the core
    // material is only its fallback.
    in.model = MaterialModel::SpecGloss;
    ExtensionReader reader(it->second, extensions_pointer + escape_pointer_token(kSpecGlossExtension), in, strict_file);
    reader.numbers("diffuseFactor", &in.diffuse[0], 4);
    reader.numbers("specularFactor", &in.legacy_specular[0], 3);
    reader.number("glossinessFactor", &in.glossiness);
    reader.texture("diffuseTexture", TextureRole::Diffuse, model);
    reader.texture("specularGlossinessTexture", TextureRole::SpecularGlossiness, model);
    if (strict_file) {
      // The schema bounds these factors to [0, 1], and a file outside it still converts. A negative
      // one reads as 0, which renders the same (no light is negative; an alpha below 0 is as
      // transparent as 0). Above 1 stays: a measured gold's F0 is 1.022, and an alpha factor above 1
      // scales a texture's alpha before viewers clamp the product.
      in.diffuse = glm::max(in.diffuse, glm::vec4(0.0f));
      in.legacy_specular = glm::max(in.legacy_specular, glm::vec3(0.0f));
    }
    // The fallback's textures are not what this model shades.
    in.textures[static_cast<size_t>(TextureRole::BaseColor)] = {};
    in.textures[static_cast<size_t>(TextureRole::MetallicRoughness)] = {};
    return in;
  }
  if (auto it = material.extensions.find(kIorExtension); it != material.extensions.end()) {
    in.has_ior = true;
    ExtensionReader(it->second, extensions_pointer + escape_pointer_token(kIorExtension), in, strict_file)
        .number("ior", &in.ior);
  }
  if (auto it = material.extensions.find(kSpecularExtension); it != material.extensions.end()) {
    in.has_specular = true;
    ExtensionReader reader(it->second, extensions_pointer + escape_pointer_token(kSpecularExtension), in, strict_file);
    reader.number("specularFactor", &in.specular);
    reader.numbers("specularColorFactor", &in.specular_color[0], 3);
    reader.texture("specularTexture", TextureRole::Specular, model);
    reader.texture("specularColorTexture", TextureRole::SpecularColor, model);
  }
  return in;
}

}  // namespace

MaterialInputs read_material_inputs(const tinygltf::Model& model, int index, SpecGlossReading spec_gloss) {
  return read_inputs(model, index, nullptr, spec_gloss);
}

MaterialInputs read_material_inputs(const Asset& asset, int index, MaterialReading reading) {
  const std::string file = asset.path.string();
  return read_inputs(asset.model, index, reading == MaterialReading::Strict ? &file : nullptr);
}

float srgb_texel_to_linear(float encoded) {
  const float code = encoded * 255.0f;
  const float rounded = std::round(code);
  if (std::abs(code - rounded) < 1e-3f && rounded >= 0.0f && rounded <= 255.0f)
    return srgb8_to_linear(static_cast<std::uint8_t>(rounded));
  return srgb_to_linear(encoded);
}

namespace {
glm::vec3 srgb_rgb(glm::vec4 texel) {
  return {srgb_texel_to_linear(texel.r), srgb_texel_to_linear(texel.g), srgb_texel_to_linear(texel.b)};
}
}  // namespace

SurfaceSample evaluate_surface(const MaterialInputs& m, const TexelInputs& texels, bool core_only) {
  SurfaceSample s;
  if (m.model == MaterialModel::SpecGloss) {
    // Archived KHR_materials_pbrSpecularGlossiness: factors multiply the linearised texels;
    // c_diff = diffuse * (1 - max(specular)), F0 = specular, alpha = (1 - glossiness)^2.
    const glm::vec3 diffuse = glm::vec3(m.diffuse) * srgb_rgb(texels[TextureRole::Diffuse]);
    const glm::vec3 specular = m.legacy_specular * srgb_rgb(texels[TextureRole::SpecularGlossiness]);
    const float glossiness = m.glossiness * texels[TextureRole::SpecularGlossiness].a;
    // A specular above 1 (gold) must not make the diffuse weight negative.
    s.c_diff = diffuse * std::max(0.0f, 1.0f - max3(specular));
    s.f0 = specular;
    s.roughness = 1.0f - glossiness;
    s.metalness = metal_likeness(mean3(specular));
    s.albedo = diffuse;
    s.dielectric_f0 = specular;
    s.metal_f0 = specular;
    s.stored_diffuse = diffuse;
    return s;
  }
  // glTF 2.0 Appendix B: F0 = mix(dielectric F0, base, metalness); the dielectric diffuse is
  // weighted by 1 - F, at normal incidence 1 - max(dielectric F0) (KHR_materials_specular: the
  // diffuse is scaled by 1 - specular * max(F)).
  const glm::vec3 base = glm::vec3(m.base_color) * srgb_rgb(texels[TextureRole::BaseColor]);
  const glm::vec4 metal_rough = texels[TextureRole::MetallicRoughness];
  s.metalness = m.metallic * metal_rough.b;
  s.roughness = m.roughness * metal_rough.g;
  glm::vec3 dielectric_f0(kDielectricF0);
  if (!core_only && (m.has_ior || m.has_specular)) {
    // KHR_materials_ior: F0 = ((ior - 1) / (ior + 1))^2. KHR_materials_specular:
    // F0 = min(F0(ior) * specularColor, 1) * specular.
    const float r = (m.ior - 1.0f) / (m.ior + 1.0f);
    dielectric_f0 = glm::vec3(r * r);
    if (m.has_specular) {
      const glm::vec3 color = m.specular_color * srgb_rgb(texels[TextureRole::SpecularColor]);
      const float weight = m.specular * texels[TextureRole::Specular].a;
      dielectric_f0 = glm::min(dielectric_f0 * color, glm::vec3(1.0f)) * weight;
    }
  }
  s.c_diff = base * (1.0f - s.metalness) * std::max(0.0f, 1.0f - max3(dielectric_f0));
  s.f0 = glm::mix(dielectric_f0, base, s.metalness);
  s.albedo = base;
  s.dielectric_f0 = dielectric_f0;
  s.metal_f0 = base;
  s.stored_diffuse = s.c_diff;
  return s;
}

glm::vec4 texel_rgba(const Pixels& p, int x, int y) {
  glm::vec4 v(1.0f);
  for (int c = 0; c < 3; ++c) v[c] = p.at(x, y, p.channels >= 3 ? c : 0);
  if (p.channels == 2 || p.channels == 4) v.a = p.at(x, y, p.channels - 1);
  return v;
}

}  // namespace gltf_pbr
