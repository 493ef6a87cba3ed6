#include "validators/mesh/triangle_mesh.hpp"

#include <map>

#include "core/accessor.hpp"
#include "core/draco.hpp"

namespace gltf_pbr::mesh {

// tinygltf leaves `mode` at -1 when the JSON omits it; glTF's default is TRIANGLES (4).
static int effective_mode(int mode) { return mode < 0 ? TINYGLTF_MODE_TRIANGLES : mode; }

bool is_triangle_mode(int mode) {
  mode = effective_mode(mode);
  return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

std::vector<Triangle> triangles_from_sequence(const std::vector<std::uint32_t>& sequence, int mode) {
  std::vector<Triangle> triangles;
  mode = effective_mode(mode);
  const std::size_t n = sequence.size();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    triangles.reserve(n / 3);
    for (std::size_t i = 0; i + 2 < n; i += 3) triangles.push_back({sequence[i], sequence[i + 1], sequence[i + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t i = 0; i + 2 < n; ++i)
      triangles.push_back(i % 2 == 0 ? Triangle{sequence[i], sequence[i + 1], sequence[i + 2]}
                                     : Triangle{sequence[i + 1], sequence[i], sequence[i + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (std::size_t i = 0; i + 2 < n; ++i) triangles.push_back({sequence[0], sequence[i + 1], sequence[i + 2]});
  }
  return triangles;
}

namespace {

// Floats halve the memory of doubles on the largest meshes, and the checks' tolerances are far
// above float precision.
using FloatArray = AccessorValues<float>;
// The vertex attributes of a primitive, by semantic, from accessors or from Draco.
using AttributeArrays = std::map<std::string, FloatArray>;

template <typename Vec, int N>
std::vector<Vec> to_vectors(const FloatArray& array) {
  std::vector<Vec> out(array.count());
  const std::size_t stride = static_cast<std::size_t>(array.components);
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int c = 0; c < N && c < array.components; ++c)
      out[i][c] = array.values[i * stride + static_cast<std::size_t>(c)];
  return out;
}

int normal_map_uv_set(const tinygltf::Model& model, const tinygltf::Primitive& primitive, bool& has_normal_map) {
  has_normal_map = false;
  if (primitive.material < 0 || static_cast<std::size_t>(primitive.material) >= model.materials.size()) return 0;
  const auto& normal_texture = model.materials[static_cast<std::size_t>(primitive.material)].normalTexture;
  has_normal_map = normal_texture.index >= 0;
  return has_normal_map ? normal_texture.texCoord : 0;
}

}  // namespace

std::optional<TriangleMesh> read_triangle_mesh(const Asset& asset, int mesh_index, int primitive_index,
                                               const MeshReadRequest& request, std::string& problem) {
  const tinygltf::Model& model = asset.model;
  const tinygltf::Primitive& primitive =
      model.meshes.at(static_cast<std::size_t>(mesh_index)).primitives.at(static_cast<std::size_t>(primitive_index));
  TriangleMesh mesh;
  const int uv_set = normal_map_uv_set(model, primitive, mesh.has_normal_map);
  const std::string uv_semantic = "TEXCOORD_" + std::to_string(uv_set);

  AttributeArrays attributes;
  std::vector<std::uint32_t> sequence;
  bool has_sequence = false;
  if (primitive.extensions.contains("KHR_draco_mesh_compression")) {
    // Decoded Draco data always has indices; attributes arrive as floats (dequantized by Draco).
    DecodedPrimitive decoded = decode_draco_primitive(asset, mesh_index, primitive_index);
    sequence = std::move(decoded.indices);
    has_sequence = true;
    mesh.has_tangent_attribute = decoded.attributes.contains("TANGENT");
    for (auto& [semantic, values] : decoded.attributes)
      attributes[semantic] = FloatArray{std::move(values), decoded.components[semantic]};
  } else {
    mesh.has_tangent_attribute = primitive.attributes.contains("TANGENT");
    auto wanted = [&](const std::string& semantic) {
      return semantic == "POSITION" || (request.normals && semantic == "NORMAL") ||
             (request.tangents && semantic == "TANGENT") || (request.uvs && semantic == uv_semantic) ||
             request.vertex_signatures;
    };
    for (const auto& [semantic, accessor] : primitive.attributes) {
      if (!wanted(semantic)) continue;
      AccessorProblem accessor_problem;
      auto array = read_accessor<float>(asset, accessor, accessor_problem);
      if (!array) {
        problem = "attribute " + semantic + ": " + accessor_problem.text();
        return std::nullopt;
      }
      attributes[semantic] = std::move(*array);
    }
    if (primitive.indices >= 0) {
      AccessorProblem accessor_problem;
      auto indices = read_index_accessor(asset, primitive.indices, accessor_problem);
      if (!indices) {
        problem = "indices: " + accessor_problem.text();
        return std::nullopt;
      }
      sequence = std::move(*indices);
      has_sequence = true;
    }
  }
  const auto position = attributes.find("POSITION");
  if (position == attributes.end() || position->second.components != 3) {
    problem = "no VEC3 POSITION attribute";
    return std::nullopt;
  }
  const std::size_t vertex_count = position->second.count();
  mesh.positions = to_vectors<glm::vec3, 3>(position->second);
  auto vertex_array = [&](const std::string& semantic, int components) -> const FloatArray* {
    const auto found = attributes.find(semantic);
    return found != attributes.end() && found->second.components == components && found->second.count() == vertex_count
               ? &found->second
               : nullptr;
  };
  if (const FloatArray* normals = request.normals ? vertex_array("NORMAL", 3) : nullptr)
    mesh.normals = to_vectors<glm::vec3, 3>(*normals);
  if (const FloatArray* tangents = request.tangents ? vertex_array("TANGENT", 4) : nullptr)
    mesh.tangents = to_vectors<glm::vec4, 4>(*tangents);
  if (const FloatArray* uvs = request.uvs ? vertex_array(uv_semantic, 2) : nullptr)
    mesh.uvs = to_vectors<glm::vec2, 2>(*uvs);
  if (request.vertex_signatures) {
    for (const auto& [semantic, array] : attributes)
      if (array.count() == vertex_count) mesh.signature_stride += static_cast<std::size_t>(array.components);
    mesh.vertex_signatures.resize(vertex_count * mesh.signature_stride);
    std::size_t column = 0;
    for (const auto& [semantic, array] : attributes) {
      if (array.count() != vertex_count) continue;
      const std::size_t components = static_cast<std::size_t>(array.components);
      for (std::size_t v = 0; v < vertex_count; ++v)
        for (std::size_t c = 0; c < components; ++c)
          mesh.vertex_signatures[v * mesh.signature_stride + column + c] = array.values[v * components + c];
      column += components;
    }
  }

  if (!has_sequence) {
    sequence.resize(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) sequence[i] = static_cast<std::uint32_t>(i);
  }
  const std::vector<Triangle> drawn = triangles_from_sequence(sequence, primitive.mode);
  mesh.triangles.reserve(drawn.size());
  mesh.triangle_numbers.reserve(drawn.size());
  for (std::size_t t = 0; t < drawn.size(); ++t) {
    const Triangle& triangle = drawn[t];
    if (triangle[0] >= vertex_count || triangle[1] >= vertex_count || triangle[2] >= vertex_count) continue;
    mesh.triangles.push_back(triangle);
    mesh.triangle_numbers.push_back(static_cast<std::uint32_t>(t));
  }
  return mesh;
}

}  // namespace gltf_pbr::mesh
