// Flattening an Asset into world-space triangles and two-sided materials (see scene.hpp): the
// node tree with its stored pose (pose.hpp), the materials and textures (scene_materials.hpp).
#include "preview/scene.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <map>

#include "core/draco.hpp"
#include "core/error.hpp"
#include "preview/pose.hpp"
#include "preview/scene_materials.hpp"

namespace gltf_pbr::preview {
namespace {

// Per-vertex tangents from UV derivatives (Lengyel 2001, "Computing Tangent Space Basis Vectors
// for an Arbitrary Mesh"), orthogonalised against the normal. The spec asks for MikkTSpace
// (glTF 2.0 section 3.7.2.1); on smooth, well-mapped meshes the two agree closely.
void generate_tangents(Scene& scene, size_t first_vertex, size_t first_triangle, int tex_coord) {
  const size_t count = scene.vertices.size() - first_vertex;
  std::vector<glm::vec3> tangent_sum(count, glm::vec3(0.0f)), bitangent_sum(count, glm::vec3(0.0f));
  for (size_t t = first_triangle; t < scene.triangles.size(); ++t) {
    const auto& tri = scene.triangles[t];
    const Vertex& a = scene.vertices[tri.vertex[0]];
    const Vertex& b = scene.vertices[tri.vertex[1]];
    const Vertex& c = scene.vertices[tri.vertex[2]];
    const glm::vec3 e1 = b.position - a.position, e2 = c.position - a.position;
    const glm::vec2 d1 = b.uv[tex_coord] - a.uv[tex_coord], d2 = c.uv[tex_coord] - a.uv[tex_coord];
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (std::abs(det) < 1e-20f) continue;
    const float r = 1.0f / det;
    const glm::vec3 tangent = (e1 * d2.y - e2 * d1.y) * r;
    const glm::vec3 bitangent = (e2 * d1.x - e1 * d2.x) * r;
    if (!std::isfinite(tangent.x + tangent.y + tangent.z + bitangent.x + bitangent.y + bitangent.z)) continue;
    for (std::uint32_t v : tri.vertex) {
      tangent_sum[v - first_vertex] += tangent;
      bitangent_sum[v - first_vertex] += bitangent;
    }
  }
  for (size_t i = 0; i < count; ++i) {
    Vertex& v = scene.vertices[first_vertex + i];
    const glm::vec3 n = v.normal;
    glm::vec3 t = tangent_sum[i] - n * glm::dot(n, tangent_sum[i]);
    const float length = glm::length(t);
    if (!(length > 1e-20f)) continue;  // w stays 0: the normal map is skipped here
    t /= length;
    const float handedness = glm::dot(glm::cross(n, t), bitangent_sum[i]) < 0.0f ? -1.0f : 1.0f;
    v.tangent = glm::vec4(t, handedness);
  }
}

void add_primitive(const Asset& asset, int mesh_index, int primitive_index, const glm::dmat4& world,
                   const Deformation& deformation, Scene& scene) {
  const tinygltf::Primitive& primitive =
      asset.model.meshes[static_cast<size_t>(mesh_index)].primitives[static_cast<size_t>(primitive_index)];
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    ++scene.stats.skipped_primitives;  // points and lines have no surface to shade
    return;
  }
  std::map<std::string, AccessorData> attributes;
  std::vector<std::uint32_t> indices;
  bool has_indices = false;
  if (primitive.extensions.count("KHR_draco_mesh_compression")) {
    DecodedPrimitive decoded = decode_draco_primitive(asset, mesh_index, primitive_index);
    ++scene.stats.draco_primitives;
    for (auto& [semantic, values] : decoded.attributes) {
      AccessorData data;
      data.components = decoded.components[semantic];
      if (data.components <= 0) continue;
      data.values.assign(values.begin(), values.end());
      attributes[semantic] = std::move(data);
    }
    indices = std::move(decoded.indices);
    has_indices = true;
  } else {
    for (const auto& [semantic, index] : primitive.attributes) {
      const bool drawn = semantic == "POSITION" || semantic == "NORMAL" || semantic == "TANGENT" ||
                         semantic == "TEXCOORD_0" || semantic == "TEXCOORD_1" || semantic == "COLOR_0";
      const bool skinning =
          !deformation.joint_matrices.empty() && (semantic.starts_with("JOINTS_") || semantic.starts_with("WEIGHTS_"));
      if (drawn || skinning) attributes[semantic] = read_attribute(asset, index);
    }
    if (primitive.indices >= 0) {
      indices = read_index_accessor_or_throw(asset, primitive.indices);
      has_indices = true;
    }
  }
  auto position_it = attributes.find("POSITION");
  if (position_it == attributes.end() || position_it->second.components != 3) {
    ++scene.stats.skipped_primitives;
    return;
  }
  const size_t vertex_count = position_it->second.count();
  for (auto& [semantic, data] : attributes)
    if (data.count() < vertex_count)
      throw InputError(asset.path.string(),
                       "/meshes/" + std::to_string(mesh_index) + "/primitives/" + std::to_string(primitive_index) +
                           "/attributes/" + semantic,
                       "has fewer elements than POSITION");
  if (!has_indices) {
    indices.resize(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i) indices[i] = static_cast<std::uint32_t>(i);
  }
  for (std::uint32_t index : indices)
    if (index >= vertex_count)
      throw InputError(
          asset.path.string(),
          "/meshes/" + std::to_string(mesh_index) + "/primitives/" + std::to_string(primitive_index) + "/indices",
          "index " + std::to_string(index) + " is past the last vertex");

  const std::string primitive_pointer =
      "/meshes/" + std::to_string(mesh_index) + "/primitives/" + std::to_string(primitive_index);
  apply_morph_targets(asset, primitive, deformation.morph_weights, attributes, primitive_pointer);
  // Section 3.7.3.3: a skinned mesh ignores its node's transform; its joints place it.
  const bool skinned = !deformation.joint_matrices.empty();
  const std::vector<glm::dmat4> skinning = skinned
                                               ? skinning_matrices(attributes, deformation.joint_matrices, vertex_count,
                                                                   asset.path.string(), primitive_pointer)
                                               : std::vector<glm::dmat4>{};
  if (skinned) ++scene.stats.skinned_primitives;
  if (!primitive.targets.empty()) ++scene.stats.morphed_primitives;
  const glm::dmat3 node_normal_matrix = glm::inverseTranspose(glm::dmat3(world));
  const glm::dmat4& winding_matrix = skinned ? deformation.joint_matrices.front() : world;
  const bool mirrored = glm::determinant(glm::dmat3(winding_matrix)) < 0.0;  // section 3.7.4: flips winding
  const size_t first_vertex = scene.vertices.size();
  const size_t first_triangle = scene.triangles.size();
  auto get = [&](const char* semantic) -> const AccessorData* {
    auto it = attributes.find(semantic);
    return it == attributes.end() ? nullptr : &it->second;
  };
  const AccessorData* normals = get("NORMAL");
  const AccessorData* tangents = get("TANGENT");
  const AccessorData* uv_sets[2] = {get("TEXCOORD_0"), get("TEXCOORD_1")};
  const AccessorData* colors = get("COLOR_0");
  for (size_t i = 0; i < vertex_count; ++i) {
    Vertex v;
    const glm::dmat4& to_world = skinned ? skinning[i] : world;
    const glm::dmat3 normal_matrix = skinned ? glm::inverseTranspose(glm::dmat3(to_world)) : node_normal_matrix;
    const double* p = position_it->second.values.data() + i * 3;
    const glm::dvec3 world_position = glm::dvec3(to_world * glm::dvec4(p[0], p[1], p[2], 1.0));
    v.position = glm::vec3(world_position);
    scene.bounds.add(world_position);
    if (normals && normals->components == 3) {
      const double* n = normals->values.data() + i * 3;
      const glm::dvec3 wn = normal_matrix * glm::dvec3(n[0], n[1], n[2]);
      const double length = glm::length(wn);
      if (length > 0.0) v.normal = glm::vec3(wn / length);
    }
    if (tangents && tangents->components == 4) {
      const double* t = tangents->values.data() + i * 4;
      const glm::dvec3 wt = glm::dmat3(to_world) * glm::dvec3(t[0], t[1], t[2]);
      const double length = glm::length(wt);
      if (length > 0.0)
        v.tangent =
            glm::vec4(glm::vec3(wt / length), static_cast<float>(t[3] < 0 ? -1 : 1) * (mirrored ? -1.0f : 1.0f));
    }
    for (int set = 0; set < 2; ++set)
      if (uv_sets[set] && uv_sets[set]->components == 2)
        v.uv[set] = glm::vec2(uv_sets[set]->values[i * 2], uv_sets[set]->values[i * 2 + 1]);
    if (colors && (colors->components == 3 || colors->components == 4)) {
      const double* c = colors->values.data() + i * static_cast<size_t>(colors->components);
      v.color = glm::vec4(c[0], c[1], c[2], colors->components == 4 ? c[3] : 1.0);
    }
    scene.vertices.push_back(v);
  }
  const std::int32_t material =
      primitive.material >= 0 && primitive.material < static_cast<int>(scene.materials.size()) - 1
          ? primitive.material
          : static_cast<std::int32_t>(scene.materials.size() - 1);
  auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (a == b || b == c || a == c) return;
    const auto base = static_cast<std::uint32_t>(first_vertex);
    if (mirrored) std::swap(b, c);
    scene.triangles.push_back({{base + a, base + b, base + c}, material});
  };
  // Section 3.7.2.1: strips alternate winding; fans share the first vertex.
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t i = 0; i + 2 < indices.size(); i += 3) emit(indices[i], indices[i + 1], indices[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < indices.size(); ++i)
      if (i % 2 == 0)
        emit(indices[i], indices[i + 1], indices[i + 2]);
      else
        emit(indices[i + 1], indices[i], indices[i + 2]);
  } else {
    for (size_t i = 1; i + 1 < indices.size(); ++i) emit(indices[0], indices[i], indices[i + 1]);
  }
  const bool has_normal_map = static_cast<size_t>(material) < asset.model.materials.size() &&
                              asset.model.materials[static_cast<size_t>(material)].normalTexture.index >= 0;
  if (has_normal_map && !tangents && normals)
    generate_tangents(scene, first_vertex, first_triangle,
                      scene.materials[static_cast<size_t>(material)].normal_texture.tex_coord);
  ++scene.stats.meshes_drawn;
}

// Draws the scene's nodes in depth-first pre-order, with a stack of its own so that a chain of any
// depth is drawn; each node once (a node under two parents or on a loop is invalid glTF: the spec's
// "Nodes and Hierarchy" makes the hierarchy a set of disjoint strict trees).
void visit_nodes(const Asset& asset, const std::vector<int>& roots, const std::vector<glm::dmat4>& node_world,
                 Scene& scene) {
  const auto& nodes = asset.model.nodes;
  std::vector<bool> drawn(nodes.size(), false);
  std::vector<std::pair<int, glm::dmat4>> stack;  // a node and its parent's world transform
  for (auto root = roots.rbegin(); root != roots.rend(); ++root) stack.emplace_back(*root, glm::dmat4(1.0));
  while (!stack.empty()) {
    const auto [node_index, parent] = stack.back();
    stack.pop_back();
    if (node_index < 0 || node_index >= static_cast<int>(nodes.size()) || drawn[static_cast<size_t>(node_index)])
      continue;
    drawn[static_cast<size_t>(node_index)] = true;
    const tinygltf::Node& node = nodes[static_cast<size_t>(node_index)];
    const glm::dmat4 world = parent * local_transform(node);
    // Skins and morph targets are drawn at rest: no animation, the pose the nodes and weights store.
    if (node.mesh >= 0 && node.mesh < static_cast<int>(asset.model.meshes.size())) {
      const Deformation deformation = node_deformation(asset, node_index, node_world);
      for (size_t p = 0; p < asset.model.meshes[static_cast<size_t>(node.mesh)].primitives.size(); ++p)
        add_primitive(asset, node.mesh, static_cast<int>(p), world, deformation, scene);
    }
    if (node.camera >= 0 && node.camera < static_cast<int>(asset.model.cameras.size())) {
      const tinygltf::Camera& camera = asset.model.cameras[static_cast<size_t>(node.camera)];
      if (camera.type == "perspective") {
        SceneCamera c;
        c.index = node.camera;
        c.camera_to_world = world;
        c.yfov = static_cast<float>(camera.perspective.yfov);
        c.znear = static_cast<float>(camera.perspective.znear);
        if (camera.perspective.zfar > 0) c.zfar = static_cast<float>(camera.perspective.zfar);
        scene.cameras.push_back(c);
      }
    }
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) stack.emplace_back(*child, world);
  }
}

}  // namespace

Scene build_scene(const Asset& original, const Asset& converted, const DecodedImages* decoded, TextureLoading loading) {
  Scene scene;
  auto loader = std::make_shared<TextureLoader>(decoded);
  read_materials(original, converted, scene, *loader);
  loader->prepare(scene);
  std::vector<int> first_levels(scene.textures.size(), 0);
  if (loading == TextureLoading::SampledLevelsLater) {
    std::fill(first_levels.begin(), first_levels.end(), TextureLoader::kNotYet);
    for (const PreviewMaterial& m : scene.materials)  // the rasterizer's alpha test samples level 0
      if (m.alpha_mode != AlphaMode::Opaque && m.base_color_texture)
        for (size_t i = 0; i < scene.textures.size(); ++i)
          if (scene.textures[i].get() == m.base_color_texture.texture) first_levels[i] = 0;
  }
  loader->load(scene, first_levels);
  if (loader->has_unloaded()) scene.unloaded = std::move(loader);
  const auto& model = original.model;
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int s =
        model.defaultScene >= 0 && model.defaultScene < static_cast<int>(model.scenes.size()) ? model.defaultScene : 0;
    roots = model.scenes[static_cast<size_t>(s)].nodes;
  } else {  // no scene: every node that is nobody's child
    std::vector<bool> is_child(model.nodes.size(), false);
    for (const auto& node : model.nodes)
      for (int c : node.children)
        if (c >= 0 && c < static_cast<int>(is_child.size())) is_child[static_cast<size_t>(c)] = true;
    for (size_t i = 0; i < model.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
  }
  const std::vector<glm::dmat4> node_world = node_world_matrices(model);
  visit_nodes(original, roots, node_world, scene);
  scene.stats.triangles = static_cast<long long>(scene.triangles.size());
  scene.stats.vertices = static_cast<long long>(scene.vertices.size());
  return scene;
}

void load_textures(Scene& scene, std::span<const int> first_levels) {
  if (!scene.unloaded) return;
  std::vector<int> levels(first_levels.begin(), first_levels.end());
  for (int& level : levels) level = std::max(level, 0);  // every texture is made now (kNotYet: all levels)
  scene.unloaded->load(scene, levels);
  scene.unloaded.reset();
}

SurfacePoint interpolate(const Scene& scene, std::uint32_t triangle, glm::vec3 b) {
  const Triangle& t = scene.triangles[triangle];
  const Vertex& v0 = scene.vertices[t.vertex[0]];
  const Vertex& v1 = scene.vertices[t.vertex[1]];
  const Vertex& v2 = scene.vertices[t.vertex[2]];
  SurfacePoint p;
  p.normal = v0.normal * b.x + v1.normal * b.y + v2.normal * b.z;
  p.face_normal = glm::cross(v1.position - v0.position, v2.position - v0.position);
  p.tangent = v0.tangent * b.x + v1.tangent * b.y + v2.tangent * b.z;
  for (int s = 0; s < 2; ++s) p.uv[s] = v0.uv[s] * b.x + v1.uv[s] * b.y + v2.uv[s] * b.z;
  p.color = v0.color * b.x + v1.color * b.y + v2.color * b.z;
  return p;
}

float surface_alpha(const Scene&, const PreviewMaterial& material, const SurfacePoint& point) {
  float alpha = material.base_color_factor.a * point.color.a;
  if (material.base_color_texture) alpha *= sample(material.base_color_texture, point.uv).a;
  return alpha;
}

}  // namespace gltf_pbr::preview
