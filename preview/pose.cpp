// The stored pose (see pose.hpp).
#include "preview/pose.hpp"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.hpp"
#include "core/json_pointer.hpp"

namespace gltf_pbr::preview {

AccessorData read_attribute(const Asset& asset, int index) {
  AccessorData data = read_accessor_or_throw(asset, index);
  for (double v : data.values)
    if (!std::isfinite(v))
      throw InputError(asset.path.string(), pointer("accessors", index), "accessor holds NaN or Inf");
  return data;
}

// --- Node transforms (glTF 2.0 section 3.5.3) ---

glm::dmat4 local_transform(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());
  glm::dmat4 m(1.0);
  if (node.translation.size() == 3)
    m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)
    m *= glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
  if (node.scale.size() == 3) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

// --- The pose the file stores (glTF 2.0 sections 3.7.2.2 and 3.7.3) ---

std::vector<glm::dmat4> node_world_matrices(const tinygltf::Model& model) {
  const std::size_t count = model.nodes.size();
  std::vector<int> parent(count, -1);
  for (std::size_t i = 0; i < count; ++i)
    for (int child : model.nodes[i].children)
      if (child >= 0 && static_cast<std::size_t>(child) < count && parent[static_cast<std::size_t>(child)] < 0)
        parent[static_cast<std::size_t>(child)] = static_cast<int>(i);
  // Down from each node without a parent, with a stack of its own: a chain of any depth, each node
  // placed once (a child listed twice is still one node). A node on a loop (invalid glTF, which no
  // root reaches) keeps its local transform.
  std::vector<glm::dmat4> world(count);
  std::vector<bool> placed(count, false);
  std::vector<std::size_t> stack;
  for (std::size_t i = 0; i < count; ++i) {
    world[i] = local_transform(model.nodes[i]);
    if (parent[i] < 0) stack.push_back(i), placed[i] = true;
  }
  while (!stack.empty()) {
    const std::size_t node = stack.back();
    stack.pop_back();
    for (int child : model.nodes[node].children) {
      const auto c = static_cast<std::size_t>(child);
      if (child < 0 || c >= count || parent[c] != static_cast<int>(node) || placed[c]) continue;
      placed[c] = true;
      world[c] = world[node] * world[c];
      stack.push_back(c);
    }
  }
  return world;
}

Deformation node_deformation(const Asset& asset, int node_index, const std::vector<glm::dmat4>& node_world) {
  const tinygltf::Model& model = asset.model;
  const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(node_index)];
  Deformation d;
  d.morph_weights = !node.weights.empty() ? node.weights : model.meshes[static_cast<std::size_t>(node.mesh)].weights;
  if (node.skin < 0) return d;
  if (static_cast<std::size_t>(node.skin) >= model.skins.size())
    throw InputError(asset.path.string(), pointer("nodes", node_index) + "/skin", "skin does not exist");
  const tinygltf::Skin& skin = model.skins[static_cast<std::size_t>(node.skin)];
  const std::string skin_pointer = pointer("skins", node.skin);
  AccessorData inverse_bind;
  if (skin.inverseBindMatrices >= 0) {
    inverse_bind = read_attribute(asset, skin.inverseBindMatrices);
    if (inverse_bind.components != 16 || inverse_bind.count() < skin.joints.size())
      throw InputError(asset.path.string(), skin_pointer + "/inverseBindMatrices",
                       "needs one MAT4 per joint (" + std::to_string(skin.joints.size()) + ")");
  }
  for (std::size_t j = 0; j < skin.joints.size(); ++j) {
    const int joint = skin.joints[j];
    if (joint < 0 || static_cast<std::size_t>(joint) >= node_world.size())
      throw InputError(asset.path.string(), skin_pointer + "/joints/" + std::to_string(j), "node does not exist");
    const glm::dmat4 bind =
        inverse_bind.values.empty() ? glm::dmat4(1.0) : glm::make_mat4(&inverse_bind.values[j * 16]);
    d.joint_matrices.push_back(node_world[static_cast<std::size_t>(joint)] * bind);
  }
  return d;
}

void apply_morph_targets(const Asset& asset, const tinygltf::Primitive& primitive, const std::vector<double>& weights,
                         std::map<std::string, AccessorData>& attributes, const std::string& primitive_pointer) {
  for (std::size_t t = 0; t < primitive.targets.size() && t < weights.size(); ++t) {
    if (weights[t] == 0.0) continue;
    for (const auto& [semantic, index] : primitive.targets[t]) {
      auto base = attributes.find(semantic);
      if (base == attributes.end() || (semantic != "POSITION" && semantic != "NORMAL" && semantic != "TANGENT"))
        continue;
      const AccessorData delta = read_attribute(asset, index);
      const std::size_t stride = static_cast<std::size_t>(base->second.components);
      if (delta.components != 3 || delta.count() != base->second.count() || stride < 3)
        throw InputError(asset.path.string(), primitive_pointer + "/targets/" + std::to_string(t) + "/" + semantic,
                         "does not match the base attribute");
      for (std::size_t v = 0; v < delta.count(); ++v)
        for (std::size_t c = 0; c < 3; ++c) base->second.values[v * stride + c] += weights[t] * delta.values[v * 3 + c];
    }
  }
}

std::vector<glm::dmat4> skinning_matrices(const std::map<std::string, AccessorData>& attributes,
                                          const std::vector<glm::dmat4>& joint_matrices, std::size_t vertex_count,
                                          const std::string& asset_path, const std::string& primitive_pointer) {
  std::vector<glm::dmat4> blended(vertex_count, glm::dmat4(0.0));
  std::vector<double> total(vertex_count, 0.0);
  for (int set = 0;; ++set) {
    auto joints = attributes.find("JOINTS_" + std::to_string(set));
    auto weights = attributes.find("WEIGHTS_" + std::to_string(set));
    if (joints == attributes.end() || weights == attributes.end()) break;
    if (joints->second.components != 4 || weights->second.components != 4)
      throw InputError(asset_path, primitive_pointer + "/attributes/" + joints->first, "JOINTS and WEIGHTS are VEC4");
    for (std::size_t v = 0; v < vertex_count; ++v)
      for (std::size_t c = 0; c < 4; ++c) {
        const double weight = weights->second.values[v * 4 + c];
        if (weight == 0.0) continue;
        const double joint = joints->second.values[v * 4 + c];
        if (!(joint >= 0 && joint < static_cast<double>(joint_matrices.size())))
          throw InputError(asset_path, primitive_pointer + "/attributes/" + joints->first,
                           "joint " + std::to_string(static_cast<long long>(joint)) + " of vertex " +
                               std::to_string(v) + " is not in the skin");
        blended[v] += weight * joint_matrices[static_cast<std::size_t>(joint)];
        total[v] += weight;
      }
  }
  for (std::size_t v = 0; v < vertex_count; ++v) blended[v] = total[v] > 0.0 ? blended[v] / total[v] : glm::dmat4(1.0);
  return blended;
}

}  // namespace gltf_pbr::preview
