// Small assets built in memory for the material and texture checks, and report queries.
#pragma once
#include <algorithm>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

#include "core/asset.hpp"
#include "core/image.hpp"
#include "core/report.hpp"
#include "rules/rule_set.hpp"
#include "test_support.hpp"
#include "validators/materials/materials.hpp"

namespace gltf_pbr::test {

// A document built in code; images are PNG-encoded bytes (as load_asset keeps them).
class AssetBuilder {
 public:
  AssetBuilder() {
    asset_.path = fs::temp_directory_path() / "built-in-memory.gltf";  // never written
    asset_.model.asset.version = "2.0";
  }
  // 8-bit texels, interleaved; returns the texture index.
  int add_png(int width, int height, int channels, const std::vector<std::uint8_t>& texels) {
    tinygltf::Image image;
    image.mimeType = "image/png";
    image.as_is = true;
    image.image = encode_png(texels, width, height, channels, 1);
    asset_.model.images.push_back(std::move(image));
    tinygltf::Texture texture;
    texture.source = static_cast<int>(asset_.model.images.size()) - 1;
    asset_.model.textures.push_back(texture);
    return static_cast<int>(asset_.model.textures.size()) - 1;
  }
  tinygltf::Material& metal_rough(glm::vec4 base, double metallic, double roughness) {
    tinygltf::Material material;
    material.pbrMetallicRoughness.baseColorFactor = {base.r, base.g, base.b, base.a};
    material.pbrMetallicRoughness.metallicFactor = metallic;
    material.pbrMetallicRoughness.roughnessFactor = roughness;
    asset_.model.materials.push_back(material);
    return asset_.model.materials.back();
  }
  tinygltf::Material& spec_gloss(glm::vec4 diffuse, glm::vec3 specular, double glossiness) {
    tinygltf::Value::Object extension;
    extension["diffuseFactor"] = numbers({diffuse.r, diffuse.g, diffuse.b, diffuse.a});
    extension["specularFactor"] = numbers({specular.r, specular.g, specular.b});
    extension["glossinessFactor"] = tinygltf::Value(glossiness);
    tinygltf::Material material;
    material.extensions["KHR_materials_pbrSpecularGlossiness"] = tinygltf::Value(std::move(extension));
    asset_.model.materials.push_back(material);
    return asset_.model.materials.back();
  }
  Asset& asset() { return asset_; }

 private:
  Asset asset_;
};

inline Report validate_in_memory(const Asset& asset, const RuleSet& rules = builtin_rules(),
                                 MaterialCheckOptions options = {}) {
  Report report;
  validate_materials(asset, rules, options, report);
  return report;
}

inline std::vector<Issue> issues_with(const Report& report, const std::string& code) {
  std::vector<Issue> found;
  std::copy_if(report.messages.begin(), report.messages.end(), std::back_inserter(found),
               [&](const Issue& issue) { return issue.code == code; });
  return found;
}

// Errors and warnings only: what "passes" means for a plausible material.
inline std::vector<Issue> problems(const Report& report) {
  std::vector<Issue> found;
  std::copy_if(report.messages.begin(), report.messages.end(), std::back_inserter(found),
               [](const Issue& issue) { return issue.severity <= Severity::Warning; });
  return found;
}

inline std::string describe(const std::vector<Issue>& issues) {
  std::string text;
  for (const Issue& issue : issues) text += "  " + issue.code + " " + issue.pointer + ": " + issue.message + "\n";
  return text;
}

}  // namespace gltf_pbr::test
