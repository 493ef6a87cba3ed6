// On-demand decoding of KHR_draco_mesh_compression primitives. Convert never calls it: Draco
// meshes stay compressed in its output. Preview and mesh checks decode through here.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/asset.hpp"

namespace gltf_pbr {

struct DecodedPrimitive {
  std::vector<std::uint32_t> indices;                    // three per triangle
  std::map<std::string, std::vector<float>> attributes;  // glTF semantic -> values, components interleaved
  std::map<std::string, int> components;                 // glTF semantic -> components per vertex
};

// The values of the attribute with Draco unique id `unique_id`, per point, components interleaved,
// as float; `components` gets its component count. std::nullopt when there is no such attribute or
// its values cannot be read as float.
std::optional<std::vector<float>> draco_attribute_values(const draco::Mesh& mesh, std::int64_t unique_id,
                                                         int& components);

// Throws InputError naming /meshes/M/primitives/P/extensions/KHR_draco_mesh_compression when the
// data is missing or does not decode (tinygltf would drop that failure silently).
DecodedPrimitive decode_draco_primitive(const Asset& asset, int mesh, int primitive);

}  // namespace gltf_pbr
