// The report's "info" block as the reference fills it (validation.schema.json "info"): version,
// extensions, resources, counts of what a renderer would draw.
#include <algorithm>

#include "validators/structure/structure_internal.hpp"

namespace gltf_pbr::structure {

void fill_info(Context& context) {
  const Document& doc = context.doc;
  // The reference describes only documents whose asset.version it understands (major 2).
  if (doc.version.empty() || !doc.version.starts_with("2.")) return;
  nlohmann::ordered_json info;
  if (!doc.version.empty()) info["version"] = doc.version;
  const Json& asset = context.root.contains("asset") ? context.root["asset"] : Json();
  if (asset.is_object()) {
    if (asset.contains("minVersion") && asset["minVersion"].is_string()) info["minVersion"] = asset["minVersion"];
    if (asset.contains("generator") && asset["generator"].is_string()) info["generator"] = asset["generator"];
  }
  if (!doc.extensions_used.empty()) info["extensionsUsed"] = doc.extensions_used;
  if (!doc.extensions_required.empty()) info["extensionsRequired"] = doc.extensions_required;
  if (!context.resources.empty()) info["resources"] = context.resources;
  info["animationCount"] = doc.animations.size();
  info["materialCount"] = doc.materials.size();
  bool morph = false, skins = !doc.skins.empty();
  std::uint64_t draw_calls = 0, vertices = 0, triangles = 0;
  int max_uvs = 0, max_influences = 0, max_attributes = 0;
  for (const auto& mesh : doc.meshes) {
    for (const auto& primitive : mesh.primitives) {
      if (!primitive.object) continue;
      ++draw_calls;
      if (primitive.targets > 0) morph = true;
      auto has = [&](const std::string& name) {
        return std::any_of(primitive.attributes.begin(), primitive.attributes.end(),
                           [&](const auto& attribute) { return attribute.first == name; });
      };
      // Sets count from 0 without gaps: TEXCOORD_1 alone gives no usable set.
      auto sets = [&](const char* prefix) {
        int n = 0;
        while (n < 64 && has(prefix + std::to_string(n))) ++n;
        return n;
      };
      const int uvs = sets("TEXCOORD_"), influences = std::min(sets("JOINTS_"), sets("WEIGHTS_")) * 4;
      std::int64_t count = -1;
      for (const auto& [name, index] : primitive.attributes) {
        if (index < 0 || static_cast<std::size_t>(index) >= doc.accessors.size()) continue;
        const std::int64_t attribute_count = doc.accessors[static_cast<std::size_t>(index)].count;
        if (name == "POSITION" || count < 0) count = attribute_count;
      }
      max_uvs = std::max(max_uvs, uvs);
      max_influences = std::max(max_influences, influences);
      max_attributes = std::max(max_attributes, static_cast<int>(primitive.attributes.size()));
      if (count > 0) vertices += static_cast<std::uint64_t>(count);
      std::int64_t elements = count;
      if (primitive.indices >= 0 && static_cast<std::size_t>(primitive.indices) < doc.accessors.size())
        elements = doc.accessors[static_cast<std::size_t>(primitive.indices)].count;
      if (elements > 0) {
        if (primitive.mode == 4) triangles += static_cast<std::uint64_t>(elements / 3);
        if ((primitive.mode == 5 || primitive.mode == 6) && elements >= 3)
          triangles += static_cast<std::uint64_t>(elements - 2);
      }
    }
  }
  info["hasMorphTargets"] = morph;
  info["hasSkins"] = skins;
  info["hasTextures"] = !doc.textures.empty();
  info["hasDefaultScene"] = context.root.contains("scene");
  info["drawCallCount"] = draw_calls;
  info["totalVertexCount"] = vertices;
  info["totalTriangleCount"] = triangles;
  info["maxUVs"] = max_uvs;
  info["maxInfluences"] = max_influences;
  info["maxAttributes"] = max_attributes;
  context.report.info = std::move(info);
}

}  // namespace gltf_pbr::structure
