#include "converter/legacy_material.hpp"

#include <cmath>

#include "core/error.hpp"

namespace gltf_pbr {
namespace {

class MaterialReader {
 public:
  MaterialReader(const Asset& asset, int material)
      : asset_(asset), base_(pointer("materials", material) + "/extensions/" + kSpecGloss) {}

  LegacyMaterial read(const tinygltf::Value& extension) const {
    LegacyMaterial legacy;
    if (!extension.IsObject()) fail("", "the extension is not an object");
    number_array(extension, "diffuseFactor", 4, &legacy.diffuse_factor[0]);
    number_array(extension, "specularFactor", 3, &legacy.specular_factor[0]);
    if (extension.Has("glossinessFactor"))
      legacy.glossiness_factor = number(extension.Get("glossinessFactor"), "/glossinessFactor");
    legacy.diffuse_texture = texture_info(extension, "diffuseTexture");
    legacy.spec_gloss_texture = texture_info(extension, "specularGlossinessTexture");
    return legacy;
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& why) const {
    throw InputError(asset_.path.string(), base_ + where, why);
  }
  float number(const tinygltf::Value& value, const std::string& where) const {
    if (!value.IsNumber()) fail(where, "not a number");
    const double v = value.GetNumberAsDouble();
    if (!std::isfinite(v)) fail(where, "is " + std::to_string(v) + "; factors must be finite");
    return static_cast<float>(v);
  }
  void number_array(const tinygltf::Value& object, const char* key, int size, float* out) const {
    if (!object.Has(key)) return;
    const tinygltf::Value& array = object.Get(key);
    if (!array.IsArray() || static_cast<int>(array.ArrayLen()) != size)
      fail(std::string("/") + key, "must be an array of " + std::to_string(size) + " numbers");
    for (int i = 0; i < size; ++i) out[i] = number(array.Get(i), std::string("/") + key + "/" + std::to_string(i));
  }
  std::optional<tinygltf::TextureInfo> texture_info(const tinygltf::Value& object, const char* key) const {
    if (!object.Has(key)) return std::nullopt;
    const tinygltf::Value& value = object.Get(key);
    const std::string where = std::string("/") + key;
    if (!value.IsObject() || !value.Get("index").IsInt()) fail(where, "textureInfo needs an integer index");
    tinygltf::TextureInfo info;
    info.index = value.Get("index").GetNumberAsInt();
    const auto& textures = asset_.model.textures;
    if (info.index < 0 || static_cast<size_t>(info.index) >= textures.size())
      fail(where + "/index", "texture " + std::to_string(info.index) + " does not exist");
    const int source = textures[static_cast<size_t>(info.index)].source;
    if (source < 0 || static_cast<size_t>(source) >= asset_.model.images.size())
      fail(where + "/index", "texture " + std::to_string(info.index) + " has no image this tool can read");
    info.texCoord = value.Get("texCoord").IsInt() ? value.Get("texCoord").GetNumberAsInt() : 0;
    if (value.Get("extensions").IsObject())
      for (const std::string& name : value.Get("extensions").Keys())
        info.extensions[name] = value.Get("extensions").Get(name);
    if (value.Get("extras").IsObject()) info.extras = value.Get("extras");
    return info;
  }

  const Asset& asset_;
  std::string base_;
};

}  // namespace

LegacyMaterial read_legacy_material(const Asset& asset, int index, const tinygltf::Value& extension) {
  return MaterialReader(asset, index).read(extension);
}

}  // namespace gltf_pbr
