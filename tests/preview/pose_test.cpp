// Skins and morph targets drawn at rest (glTF 2.0 sections 3.7.2.2 and 3.7.3): the pose the nodes
// and weights store, without animation.
#include <gtest/gtest.h>

#include "core/accessor.hpp"
#include "core/error.hpp"
#include "preview/preview.hpp"

namespace gltf_pbr::preview {
namespace {

// One triangle (0,0,0) (1,0,0) (0,1,0) on node 0, built piece by piece by each test.
struct TriangleAsset {
  Asset asset;
  tinygltf::Primitive primitive;

  TriangleAsset() {
    asset.path = "pose.gltf";
    primitive.attributes["POSITION"] =
        add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
  }

  template <typename T>
  int add(const std::vector<T>& values, int component, int type) {
    return append_accessor(asset.model, values, component, type);
  }

  Scene build(tinygltf::Node node, std::vector<double> mesh_weights = {}, std::vector<tinygltf::Node> more = {}) {
    tinygltf::Mesh mesh;
    mesh.primitives.push_back(primitive);
    mesh.weights = std::move(mesh_weights);
    asset.model.meshes = {mesh};
    node.mesh = 0;
    if (!asset.model.skins.empty()) node.skin = 0;
    asset.model.nodes = {node};
    for (auto& extra : more) asset.model.nodes.push_back(extra);
    tinygltf::Scene scene;
    scene.nodes = {0};
    asset.model.scenes = {scene};
    return build_scene(asset, asset);
  }

  // Every vertex bound with weight 1 to joint `joint` of a skin whose joints are nodes 1 and 2.
  void bind_all_vertices_to(std::uint8_t joint, const std::vector<float>& inverse_bind_matrices = {}) {
    const std::vector<std::uint8_t> joints = {joint, 0, 0, 0, joint, 0, 0, 0, joint, 0, 0, 0};
    const std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    primitive.attributes["JOINTS_0"] = add(joints, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4);
    primitive.attributes["WEIGHTS_0"] = add(weights, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4);
    tinygltf::Skin skin;
    skin.joints = {1, 2};
    if (!inverse_bind_matrices.empty())
      skin.inverseBindMatrices = add(inverse_bind_matrices, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4);
    asset.model.skins = {skin};
  }
};

tinygltf::Node translated(double x, double y, double z) {
  tinygltf::Node node;
  node.translation = {x, y, z};
  return node;
}

TEST(Pose, MorphTargetsApplyTheMeshWeightsUnlessTheNodeHasItsOwn) {
  TriangleAsset triangle;
  const std::vector<float> delta = {0, 2, 0, 0, 2, 0, 0, 2, 0};
  triangle.primitive.targets.push_back(
      {{"POSITION", triangle.add(delta, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3)}});
  const Scene by_mesh = triangle.build(tinygltf::Node{}, {0.5});
  EXPECT_EQ(by_mesh.vertices[1].position, glm::vec3(1, 1, 0));
  EXPECT_EQ(by_mesh.stats.morphed_primitives, 1);
  tinygltf::Node overriding;
  overriding.weights = {1.5};
  EXPECT_EQ(triangle.build(overriding, {0.5}).vertices[1].position, glm::vec3(1, 3, 0));
  EXPECT_EQ(triangle.build(tinygltf::Node{}).vertices[1].position, glm::vec3(1, 0, 0));  // no weights: base
}

TEST(Pose, SkinnedVerticesFollowTheirJointAndIgnoreTheirNode) {
  TriangleAsset triangle;
  triangle.bind_all_vertices_to(1);
  // The mesh's node is moved far away; spec 3.7.3.3 says its transform does not apply.
  const Scene scene = triangle.build(translated(100, 0, 0), {}, {translated(1, 0, 0), translated(0, 0, 5)});
  EXPECT_EQ(scene.stats.skinned_primitives, 1);
  EXPECT_EQ(scene.vertices[0].position, glm::vec3(0, 0, 5));  // joint 1 is node 2
  EXPECT_EQ(scene.vertices[1].position, glm::vec3(1, 0, 5));
}

TEST(Pose, JointsAtTheirBindPoseDrawTheMeshAsStored) {
  TriangleAsset triangle;
  // Inverse bind matrices (column-major) undo the joints' translations (1,0,0) and (0,0,5).
  const std::vector<float> inverse_bind = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1,
                                           1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1};
  triangle.bind_all_vertices_to(1, inverse_bind);
  const Scene scene = triangle.build(tinygltf::Node{}, {}, {translated(1, 0, 0), translated(0, 0, 5)});
  EXPECT_EQ(scene.stats.skinned_primitives, 1);
  EXPECT_EQ(scene.vertices[1].position, glm::vec3(1, 0, 0));
  EXPECT_EQ(scene.vertices[2].position, glm::vec3(0, 1, 0));
}

TEST(Pose, AMeshUnderAChainOfAnyDepthIsDrawnWhereItsNodesPutIt) {
  // Node 0 is the top of a 1000-node chain, each node one unit up; the mesh hangs on the last.
  constexpr int kDepth = 1000;
  TriangleAsset triangle;
  std::vector<tinygltf::Node> chain;
  for (int i = 1; i < kDepth; ++i) chain.push_back(translated(0, 1, 0));
  for (int i = 0; i + 1 < kDepth - 1; ++i) chain[static_cast<size_t>(i)].children = {i + 2};
  tinygltf::Node top = translated(0, 1, 0);
  top.children = {1};
  // build() puts the mesh on node 0, the top: move it to the bottom of the chain.
  Scene scene = triangle.build(top, {}, chain);
  ASSERT_EQ(scene.vertices.size(), 3u);
  EXPECT_EQ(scene.vertices[1].position, glm::vec3(1, 1, 0));
  triangle.asset.model.nodes[0].mesh = -1;
  triangle.asset.model.nodes[kDepth - 1].mesh = 0;
  scene = build_scene(triangle.asset, triangle.asset);
  ASSERT_EQ(scene.vertices.size(), 3u);
  EXPECT_EQ(scene.vertices[1].position, glm::vec3(1, kDepth, 0));
  // A node that is its own ancestor (invalid glTF) is drawn once, and the build ends.
  triangle.asset.model.nodes[kDepth - 1].children = {0};
  EXPECT_EQ(build_scene(triangle.asset, triangle.asset).vertices.size(), 3u);
}

TEST(Pose, AJointAtTheEndOfADeepChainWithChildrenListedTwiceTakesTheWholeChainOnce) {
  // The skin's joint 1 (node 2) ends a 100-node chain under node 1, each node one unit up and
  // listing its child twice (invalid glTF): its world transform is the chain's, 100 units up, and
  // the walk places each node once (listed twice per level, 2^100 visits otherwise).
  constexpr int kDepth = 100;
  TriangleAsset triangle;
  triangle.bind_all_vertices_to(1);
  std::vector<tinygltf::Node> more(static_cast<size_t>(kDepth), translated(0, 1, 0));
  more[0].children = {3, 3};  // node 1, the chain's top; then nodes 3 .. kDepth, and node 2 at the end
  for (int i = 2; i < kDepth; ++i) more[static_cast<size_t>(i)].children = {i + 2, i + 2};
  more[static_cast<size_t>(kDepth - 1)].children = {2, 2};  // node kDepth, above the joint
  const Scene scene = triangle.build(tinygltf::Node{}, {}, more);
  ASSERT_EQ(scene.stats.skinned_primitives, 1);
  EXPECT_EQ(scene.vertices[1].position, glm::vec3(1, kDepth, 0));
}

TEST(Pose, JointIndexOutsideTheSkinIsBadInputNamingTheAttribute) {
  TriangleAsset triangle;
  triangle.bind_all_vertices_to(7);
  try {
    triangle.build(tinygltf::Node{}, {}, {translated(1, 0, 0), translated(0, 0, 5)});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/meshes/0/primitives/0/attributes/JOINTS_0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gltf_pbr::preview
