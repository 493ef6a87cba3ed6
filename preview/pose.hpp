// The pose a file stores, drawn at rest (no animation): node transforms (glTF 2.0 section 3.5.3),
// morph targets (section 3.7.2.2) and skins (section 3.7.3), in double precision. Bad input
// throws InputError naming the file and the JSON pointer.
#pragma once
#include <glm/mat4x4.hpp>
#include <map>
#include <string>
#include <vector>

#include "core/accessor.hpp"
#include "core/asset.hpp"

namespace gltf_pbr::preview {

using AccessorData = AccessorValues<double>;

// An attribute accessor in doubles (positions go through the node transforms in double); NaN or
// Inf would reach the rasterizer, so they are bad input here.
AccessorData read_attribute(const Asset& asset, int index);

// A node's own matrix, or T * R * S from its translation, rotation and scale.
glm::dmat4 local_transform(const tinygltf::Node& node);

// World matrix of every node, drawn or not: a skin's joints may sit outside the drawn scene.
// A node in a loop or deeper than the visit limit keeps its local matrix.
std::vector<glm::dmat4> node_world_matrices(const tinygltf::Model& model);

// How a node deforms its mesh at rest: morph target weights (the node's, else the mesh's, else
// none) and, for a skinned mesh, one matrix per joint, world(joint) · inverseBindMatrix. When the
// joints are stored at their bind pose this draws the mesh as stored.
struct Deformation {
  std::vector<double> morph_weights;
  std::vector<glm::dmat4> joint_matrices;  // empty: not skinned
};
Deformation node_deformation(const Asset& asset, int node_index, const std::vector<glm::dmat4>& node_world);

// Section 3.7.2.2: the rest shape is the base plus each target's deltas times its weight.
void apply_morph_targets(const Asset& asset, const tinygltf::Primitive& primitive, const std::vector<double>& weights,
                         std::map<std::string, AccessorData>& attributes, const std::string& primitive_pointer);

// Section 3.7.3.3: a skinned vertex moves by the weighted sum of its joints' matrices, over every
// JOINTS_n/WEIGHTS_n set. Weights are renormalised (the validator reports sums off one); a
// vertex with no weight at all stays as stored.
std::vector<glm::dmat4> skinning_matrices(const std::map<std::string, AccessorData>& attributes,
                                          const std::vector<glm::dmat4>& joint_matrices, std::size_t vertex_count,
                                          const std::string& asset_path, const std::string& primitive_pointer);

}  // namespace gltf_pbr::preview
