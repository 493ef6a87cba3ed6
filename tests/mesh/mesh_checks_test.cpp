// Mesh checks (validators/mesh): each constructed defect gives exactly its MESH_* issue, the same
// mesh without the defect gives none; real assets (2CylinderEngine, its Draco twin) and a Draco
// stream made here with libdraco's encoder.
#include "validators/mesh/mesh_checks.hpp"

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <glm/geometric.hpp>
#include <limits>
#include <map>

#include "core/accessor.hpp"
#include "core/asset.hpp"
#include "rules/rule_set.hpp"
#include "validators/mesh/triangle_mesh.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

fs::path shared_assets() { return fs::path(GLTF_PBR_SHARED_DIR) / "assets"; }

// ---- Building small assets in memory ----

struct TestMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec4> tangents;
  std::vector<glm::vec2> uvs;
  std::vector<std::uint32_t> indices;  // empty: non-indexed
  int mode = TINYGLTF_MODE_TRIANGLES;
  bool normal_map = false;
};

Asset make_asset(const TestMesh& mesh) {
  Asset asset;
  tinygltf::Model& model = asset.model;
  tinygltf::Primitive primitive;
  primitive.mode = mesh.mode;
  primitive.attributes["POSITION"] =
      append_accessor(model, mesh.positions, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  if (!mesh.normals.empty())
    primitive.attributes["NORMAL"] =
        append_accessor(model, mesh.normals, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  if (!mesh.tangents.empty())
    primitive.attributes["TANGENT"] =
        append_accessor(model, mesh.tangents, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4);
  if (!mesh.uvs.empty())
    primitive.attributes["TEXCOORD_0"] =
        append_accessor(model, mesh.uvs, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2);
  if (!mesh.indices.empty())
    primitive.indices =
        append_accessor(model, mesh.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR);
  if (mesh.normal_map) {
    model.images.resize(1);
    model.textures.resize(1);
    model.textures[0].source = 0;
    model.materials.resize(1);
    model.materials[0].normalTexture.index = 0;
    primitive.material = 0;
  }
  model.meshes.resize(1);
  model.meshes[0].primitives.push_back(primitive);
  return asset;
}

// A unit cube of 12 outward-facing counter-clockwise triangles, flat-shaded: 24 vertices (4 per
// side, so sides are split at the edges as exporters write them) with normals.
TestMesh cube() {
  TestMesh mesh;
  const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {1.0f, -1.0f}) {
      const glm::vec3 n = axes[axis] * sign;
      const glm::vec3 u = axes[(axis + 1) % 3] * sign, v = axes[(axis + 2) % 3];
      // Corners c - u - v, c + u - v, c + u + v, c - u + v, with cross(u, v) = n.
      const glm::vec3 centre = n * 0.5f;
      const auto base = static_cast<std::uint32_t>(mesh.positions.size());
      for (auto [a, b] : {std::pair{-1.f, -1.f}, {1.f, -1.f}, {1.f, 1.f}, {-1.f, 1.f}}) {
        mesh.positions.push_back(centre + 0.5f * (a * u + b * v));
        mesh.normals.push_back(n);
        mesh.uvs.push_back({0.5f + 0.5f * a, 0.5f - 0.5f * b});
      }
      for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + k);
    }
  return mesh;
}

// The same cube as 8 shared corners and nothing but positions.
TestMesh welded_cube() {
  TestMesh mesh;
  for (int corner = 0; corner < 8; ++corner)
    mesh.positions.push_back({corner & 1 ? 0.5f : -0.5f, corner & 2 ? 0.5f : -0.5f, corner & 4 ? 0.5f : -0.5f});
  // Counter-clockwise seen from outside, two per side.
  mesh.indices = {1, 3, 7, 1, 7, 5, 0, 4, 6, 0, 6, 2, 2, 6, 7, 2, 7, 3,
                  0, 1, 5, 0, 5, 4, 4, 5, 7, 4, 7, 6, 0, 2, 3, 0, 3, 1};
  return mesh;
}

// A unit quad in z = 0 facing +z: glTF UVs (origin top-left), normals +z, tangents +x with w +1.
TestMesh quad() {
  TestMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.normals.assign(4, {0, 0, 1});
  mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  mesh.tangents.assign(4, {1, 0, 0, 1});
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

Report validate(const Asset& asset, const RuleSet& rules = builtin_rules(), MeshCheckOptions options = {}) {
  Report report;
  validate_meshes(asset, rules, options, report);
  return report;
}

std::vector<std::string> codes(const Report& report) {
  std::vector<std::string> out;
  for (const Issue& issue : report.messages) out.push_back(issue.code);
  return out;
}

// Every MESH_* rule on, the opt-in ones too.
RuleSet all_rules_on() {
  RuleSet rules = builtin_rules();
  for (const auto& [code, rule] : builtin_rules().all())
    if (code.starts_with("MESH_")) rules.mutable_rule(code).enabled = true;
  return rules;
}

using Codes = std::vector<std::string>;

// ---- Clean meshes ----

TEST(MeshChecks, ClosedCubeHasNoIssuesEvenWithEveryRuleOn) {
  EXPECT_EQ(codes(validate(make_asset(cube()), all_rules_on())), Codes{});
}

TEST(MeshChecks, QuadWithConsistentTangentsHasNoIssues) {
  TestMesh mesh = quad();
  mesh.normal_map = true;
  EXPECT_EQ(codes(validate(make_asset(mesh))), Codes{});
}

// ---- Degenerate and needle triangles ----

TEST(MeshChecks, RepeatedIndexTriangleIsDegenerateAndNamed) {
  TestMesh mesh = cube();
  mesh.indices.insert(mesh.indices.end(), {0, 0, 1});  // triangle 12
  const Report report = validate(make_asset(mesh));
  ASSERT_EQ(codes(report), Codes{"MESH_TRIANGLE_DEGENERATE"});
  EXPECT_EQ(report.messages[0].pointer, "/meshes/0/primitives/0");
  EXPECT_EQ(report.messages[0].severity, Severity::Information);
  EXPECT_NE(report.messages[0].message.find("1 degenerate triangles"), std::string::npos) << report.messages[0].message;
  EXPECT_NE(report.messages[0].message.find("first: 12."), std::string::npos) << report.messages[0].message;
}

TEST(MeshChecks, CollinearAndCoincidentTrianglesAreDegenerate) {
  TestMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 0}, {5, 5, 5}};
  mesh.uvs = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}};  // vertex 3 is a seam copy of 0, not a duplicate
  mesh.indices = {0, 1, 2, 0, 3, 4};                    // collinear; two indices at one position
  const Report report = validate(make_asset(mesh));
  ASSERT_EQ(codes(report), Codes{"MESH_TRIANGLE_DEGENERATE"});
  EXPECT_NE(report.messages[0].message.find("2 degenerate triangles"), std::string::npos);
}

TEST(MeshChecks, NeedleTriangleIsReportedAndAWellShapedOneIsNot) {
  TestMesh needle;
  needle.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1e-4f, 0.5f}};  // edge (1,2) is 1e-4 long beside edges ~1.1
  needle.positions[2] = {1.0f, 0.0f, 1e-4f};
  needle.indices = {0, 1, 2};
  EXPECT_EQ(codes(validate(make_asset(needle))), Codes{"MESH_TRIANGLE_NEEDLE"});
  TestMesh good = needle;
  good.positions[2] = {0.5f, 0.8f, 0.0f};
  EXPECT_EQ(codes(validate(make_asset(good))), Codes{});
}

// ---- Duplicates ----

TEST(MeshChecks, RepeatedTriangleInEitherWindingIsADuplicateOnly) {
  for (bool flip : {false, true}) {
    TestMesh mesh = cube();
    mesh.indices.insert(mesh.indices.end(), {flip ? 2u : 0u, 1u, flip ? 0u : 2u});
    const Report report = validate(make_asset(mesh), all_rules_on());
    ASSERT_EQ(codes(report), Codes{"MESH_TRIANGLE_DUPLICATE"}) << "flip " << flip;
    EXPECT_NE(report.messages[0].message.find("first: 12."), std::string::npos) << report.messages[0].message;
  }
}

TEST(MeshChecks, VertexEqualInEveryAttributeIsADuplicate) {
  TestMesh mesh = cube();
  mesh.positions.push_back(mesh.positions[0]);
  mesh.normals.push_back(mesh.normals[0]);
  mesh.uvs.push_back(mesh.uvs[0]);
  mesh.indices[0] = 24;
  const Report report = validate(make_asset(mesh), all_rules_on());
  ASSERT_EQ(codes(report), Codes{"MESH_VERTEX_DUPLICATE"});
  EXPECT_NE(report.messages[0].message.find("first: 24."), std::string::npos) << report.messages[0].message;
  // A position shared with another normal (a seam) is no duplicate: the plain cube has 3 per corner.
  EXPECT_EQ(codes(validate(make_asset(cube()), all_rules_on())), Codes{});
}

// ---- Topology ----

TEST(MeshChecks, EdgeSharedByThreeTrianglesIsNonManifold) {
  TestMesh fins;
  fins.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0.5f, 0}, {-1, -0.5f, 0}};
  fins.indices = {0, 1, 2, 1, 0, 3, 1, 0, 4};
  EXPECT_EQ(codes(validate(make_asset(fins))), Codes{"MESH_EDGE_NON_MANIFOLD"});
  TestMesh two = fins;
  two.indices.resize(6);
  EXPECT_EQ(codes(validate(make_asset(two))), Codes{});
}

TEST(MeshChecks, TrianglesMeetingInOnlyOneVertexMakeItNonManifold) {
  TestMesh bowtie;
  bowtie.positions = {{0, 0, 0}, {1, 1, 0}, {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}};
  bowtie.indices = {0, 1, 2, 0, 4, 3};
  const Report report = validate(make_asset(bowtie));
  ASSERT_EQ(codes(report), Codes{"MESH_VERTEX_NON_MANIFOLD"});
  EXPECT_NE(report.messages[0].message.find("first vertices: 0."), std::string::npos) << report.messages[0].message;
  TestMesh joined = bowtie;  // the same fan closed over an edge is a disk
  joined.indices = {0, 1, 2, 0, 2, 1 + 3};
  joined.positions[4] = {-1, 0, 0};
  joined.indices = {0, 1, 2, 0, 2, 4};
  EXPECT_EQ(codes(validate(make_asset(joined))), Codes{});
}

TEST(MeshChecks, BorderEdgesAreReportedOnlyWhenTheRuleIsSwitchedOn) {
  TestMesh open = cube();
  open.indices.resize(open.indices.size() - 6);           // one side removed: 4 border edges
  EXPECT_EQ(codes(validate(make_asset(open))), Codes{});  // off by default
  const Report report = validate(make_asset(open), all_rules_on());
  ASSERT_EQ(codes(report), Codes{"MESH_EDGE_BORDER"});
  EXPECT_NE(report.messages[0].message.find("4 border edges"), std::string::npos) << report.messages[0].message;
}

TEST(MeshChecks, OneTriangleWoundAgainstItsNeighboursIsInconsistentWinding) {
  EXPECT_EQ(codes(validate(make_asset(welded_cube()), all_rules_on())), Codes{});
  TestMesh mesh = welded_cube();                // without normals the flip shows only as winding
  std::swap(mesh.indices[1], mesh.indices[2]);  // triangle 0 reversed
  const Report report = validate(make_asset(mesh));
  ASSERT_EQ(codes(report), Codes{"MESH_WINDING_INCONSISTENT"});
  EXPECT_NE(report.messages[0].message.find("3 edges"), std::string::npos) << report.messages[0].message;
  TestMesh with_normals = cube();
  std::swap(with_normals.indices[1], with_normals.indices[2]);
  EXPECT_EQ(codes(validate(make_asset(with_normals))), (Codes{"MESH_WINDING_INCONSISTENT", "MESH_NORMAL_FLIPPED"}));
}

// ---- Self-intersections ----

TestMesh crossing_triangles(float separation) {
  TestMesh mesh;
  mesh.positions = {
      {-1, -1, 0},           {1, -1, 0}, {0, 1, 0}, {0, -0.5f, -1 + separation}, {0, 0.5f, -1 + separation},
      {0, 0, 1 + separation}};
  mesh.indices = {0, 1, 2, 3, 4, 5};
  return mesh;
}

TEST(MeshChecks, CrossingTrianglesIntersectAndSeparatedOnesDoNot) {
  const Report report = validate(make_asset(crossing_triangles(0)));
  ASSERT_EQ(codes(report), Codes{"MESH_SELF_INTERSECTION"});
  EXPECT_NE(report.messages[0].message.find("1 pairs"), std::string::npos) << report.messages[0].message;
  EXPECT_NE(report.messages[0].message.find("first pairs: 0/1."), std::string::npos) << report.messages[0].message;
  EXPECT_EQ(codes(validate(make_asset(crossing_triangles(3)))), Codes{});
}

TEST(MeshChecks, SelfIntersectionCheckIsSwitchableByOptionAndRule) {
  const Asset asset = make_asset(crossing_triangles(0));
  EXPECT_EQ(codes(validate(asset, builtin_rules(), MeshCheckOptions{false})), Codes{});
  RuleSet rules = builtin_rules();
  rules.mutable_rule("MESH_SELF_INTERSECTION").enabled = false;
  EXPECT_EQ(codes(validate(asset, rules)), Codes{});
}

TEST(MeshChecks, SelfIntersectionSearchStopsAtMaxPairs) {
  TestMesh mesh;  // 10 horizontal triangles pierced by 10 vertical ones: 100 pairs
  for (int i = 0; i < 10; ++i) {
    const float z = 0.1f * i, x = -0.45f + 0.1f * i;
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(),
                          {{-2, -2, z}, {2, -2, z}, {0, 2, z}, {x, -0.5f, -1}, {x, 0.5f, -1}, {x, 0, 2}});
    for (std::uint32_t k = 0; k < 6; ++k) mesh.indices.push_back(base + k);
  }
  RuleSet rules = builtin_rules();
  rules.mutable_rule("MESH_SELF_INTERSECTION").thresholds["max_pairs"] = 7;
  const Report report = validate(make_asset(mesh), rules);
  ASSERT_EQ(codes(report), Codes{"MESH_SELF_INTERSECTION"});
  EXPECT_NE(report.messages[0].message.find("At least 7 pairs"), std::string::npos) << report.messages[0].message;
}

TEST(MeshChecks, CoplanarNeighboursFoldedOverEachOtherIntersect) {
  TestMesh folded;  // two triangles on one edge, both on the same side of it, in one plane
  folded.positions = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, 0.5f, 0}};
  folded.indices = {0, 1, 2, 1, 0, 3};
  EXPECT_EQ(codes(validate(make_asset(folded))), Codes{"MESH_SELF_INTERSECTION"});
  folded.positions[3] = {0.5f, -1, 0};  // unfolded: a flat quad
  EXPECT_EQ(codes(validate(make_asset(folded))), Codes{});
}

// ---- Normals, tangents, UVs ----

TEST(MeshChecks, InvertedNormalsAreFlipped) {
  TestMesh mesh = cube();
  for (glm::vec3& n : mesh.normals) n = -n;
  const Report report = validate(make_asset(mesh));
  ASSERT_EQ(codes(report), Codes{"MESH_NORMAL_FLIPPED"});
  EXPECT_NE(report.messages[0].message.find("12 triangles"), std::string::npos) << report.messages[0].message;
}

TEST(MeshChecks, TangentLeaningTowardsTheNormalIsNotOrthogonal) {
  TestMesh mesh = quad();
  mesh.tangents[2] = {0.8f, 0, 0.6f, 1};  // cos 0.6 with the normal
  const Report report = validate(make_asset(mesh));
  ASSERT_EQ(codes(report), Codes{"MESH_TANGENT_NOT_ORTHOGONAL"});
  EXPECT_NE(report.messages[0].message.find("first vertices: 2."), std::string::npos) << report.messages[0].message;
}

TEST(MeshChecks, TangentWithTheWrongSignOfWIsWrongHanded) {
  TestMesh mesh = quad();
  mesh.tangents[1].w = -1;
  const Report report = validate(make_asset(mesh));
  ASSERT_EQ(codes(report), Codes{"MESH_TANGENT_HANDEDNESS"});
  EXPECT_NE(report.messages[0].message.find("first vertices: 1."), std::string::npos) << report.messages[0].message;
  // Mirrored UVs (u reversed) ask for w = -1: then -1 is right and +1 wrong.
  TestMesh mirrored = quad();
  for (glm::vec2& uv : mirrored.uvs) uv.x = 1 - uv.x;
  for (glm::vec4& t : mirrored.tangents) t = {-1, 0, 0, -1};
  EXPECT_EQ(codes(validate(make_asset(mirrored))), Codes{});
}

TEST(MeshChecks, ZeroAreaUvTriangleMattersWhereANormalMapNeedsGeneratedTangents) {
  TestMesh mesh = quad();
  mesh.tangents.clear();
  mesh.normal_map = true;
  mesh.uvs[2] = mesh.uvs[0];  // triangle 0 and 1 lose their UV area: (0,1),(1,1),(0,1) and (0,1),(0,1),(0,0)
  const Report report = validate(make_asset(mesh));
  ASSERT_EQ(codes(report), Codes{"MESH_UV_DEGENERATE"});
  EXPECT_NE(report.messages[0].message.find("2 triangles"), std::string::npos) << report.messages[0].message;
  TestMesh no_normal_map = mesh;  // nothing needs tangents
  no_normal_map.normal_map = false;
  EXPECT_EQ(codes(validate(make_asset(no_normal_map))), Codes{});
  TestMesh with_tangents = mesh;  // tangents given: none generated
  with_tangents.tangents.assign(4, {1, 0, 0, 1});
  EXPECT_EQ(codes(validate(make_asset(with_tangents))), Codes{});
}

// ---- Modes ----

TEST(MeshChecks, StripAndFanAreUnrolledWithTheirWindingKept) {
  TestMesh strip;  // a 2x1 strip of 4 triangles, consistently wound by the strip rule
  strip.positions = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}, {2, 1, 0}};
  strip.normals.assign(6, {0, 0, -1});  // strip (0,1,2) is clockwise seen from +z: faces -z
  strip.mode = TINYGLTF_MODE_TRIANGLE_STRIP;
  EXPECT_EQ(codes(validate(make_asset(strip))), Codes{});
  // Two strips stitched into one by repeating an index at each end (4 degenerate triangles that
  // keep the strip's parity, so the second strip keeps the first one's winding).
  TestMesh stitched;
  stitched.positions = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {3, 0, 0}, {3, 1, 0}, {4, 0, 0}, {4, 1, 0}};
  stitched.normals.assign(8, {0, 0, -1});
  stitched.mode = TINYGLTF_MODE_TRIANGLE_STRIP;
  stitched.indices = {0, 1, 2, 3, 3, 4, 4, 5, 6, 7};
  const Report report = validate(make_asset(stitched));
  ASSERT_EQ(codes(report), Codes{"MESH_TRIANGLE_DEGENERATE"});
  EXPECT_NE(report.messages[0].message.find("4 degenerate triangles"), std::string::npos) << report.messages[0].message;
  EXPECT_NE(report.messages[0].message.find("first: 2, 3, 4, 5."), std::string::npos) << report.messages[0].message;

  TestMesh fan;
  fan.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}};
  fan.normals.assign(5, {0, 0, 1});
  fan.mode = TINYGLTF_MODE_TRIANGLE_FAN;
  EXPECT_EQ(codes(validate(make_asset(fan))), Codes{});
  for (glm::vec3& n : fan.normals) n = -n;
  EXPECT_EQ(codes(validate(make_asset(fan))), Codes{"MESH_NORMAL_FLIPPED"});
}

TEST(MeshChecks, PointsAndLinesAreNotRead) {
  TestMesh points = crossing_triangles(0);
  points.mode = TINYGLTF_MODE_POINTS;
  EXPECT_EQ(codes(validate(make_asset(points))), Codes{});
}

// ---- Real assets ----

// The Khronos glTF-Validator reports ACCESSOR_INDEX_TRIANGLE_DEGENERATE (info) on 25 indices
// accessors of 2CylinderEngine (shared/assets/README.md): meshes 1-5 and 7-26, primitive 0, with
// 10413 repeated-index triangles. Six more triangles there repeat a position under two indices.
TEST(MeshChecks, TwoCylinderEngineDegenerateTrianglesMatchTheKhronosValidator) {
  const Asset asset = load_asset(shared_assets() / "2CylinderEngine/metalrough/2CylinderEngine.gltf");
  RuleSet rules = builtin_rules();
  for (const auto& [code, rule] : builtin_rules().all())
    if (code.starts_with("MESH_")) rules.mutable_rule(code).enabled = code == "MESH_TRIANGLE_DEGENERATE";
  const Report report = validate(asset, rules);
  std::vector<std::string> pointers;
  std::uint64_t triangles = 0;
  for (const Issue& issue : report.messages) {
    EXPECT_EQ(issue.code, "MESH_TRIANGLE_DEGENERATE");
    EXPECT_EQ(issue.severity, Severity::Information);
    pointers.push_back(issue.pointer);
    triangles += std::stoull(issue.message);
  }
  std::vector<std::string> expected;
  for (int mesh = 1; mesh <= 26; ++mesh)
    if (mesh != 6) expected.push_back("/meshes/" + std::to_string(mesh) + "/primitives/0");
  EXPECT_EQ(pointers, expected);
  EXPECT_EQ(triangles, 10413u + 6u);
}

TEST(MeshChecks, SharedAssetsReport) {
  // Not an assertion of exact counts beyond the Khronos anchor: prints what the checks find on the
  // shared assets, and checks the step runs on each without an unreadable primitive.
  for (const char* file :
       {"2CylinderEngine/metalrough/2CylinderEngine.gltf", "VC/metalrough/VC.gltf", "Avocado/metalrough/Avocado.gltf",
        "Duck/metalrough/Duck.gltf", "2CylinderEngine/metalrough-draco/2CylinderEngine.gltf"}) {
    const Report report = validate(load_asset(shared_assets() / file));
    std::map<std::string, int> per_code;
    for (const Issue& issue : report.messages) {
      ++per_code[issue.code];
      EXPECT_NE(issue.code, "MESH_PRIMITIVE_UNREADABLE") << file << ": " << issue.message;
    }
    std::string summary;
    for (const auto& [code, count] : per_code) summary += " " + code + "=" + std::to_string(count);
    std::printf("%s:%s\n", file, summary.c_str());
    if (std::getenv("MESH_TEST_VERBOSE"))
      for (const Issue& issue : report.messages)
        std::printf("  %s %s %s\n", issue.code.c_str(), issue.pointer.c_str(), issue.message.c_str());
  }
}

TEST(MeshChecks, AvocadoTangentsAgreeWithTheHandednessConvention) {
  // Avocado ships TANGENT and a normal map: the reference for which sign of w glTF UVs ask for.
  const Asset asset = load_asset(shared_assets() / "Avocado/metalrough/Avocado.gltf");
  const Report report = validate(asset);
  for (const Issue& issue : report.messages) EXPECT_NE(issue.code, "MESH_TANGENT_HANDEDNESS") << issue.message;
  // The opposite convention would call most of its vertices wrong-handed.
  std::string problem;
  auto read = mesh::read_triangle_mesh(asset, 0, 0, {true, true, true, false}, problem);
  ASSERT_TRUE(read) << problem;
  ASSERT_FALSE(read->tangents.empty());
  const mesh::WeldedMesh welded = mesh::weld(*read, {});
  EXPECT_EQ(mesh::find_wrong_handedness(*read, welded).size(), 0u);
  for (glm::vec4& tangent : read->tangents) tangent.w = -tangent.w;
  EXPECT_GT(mesh::find_wrong_handedness(*read, welded).size(), read->tangents.size() / 2);
}

TEST(MeshChecks, ValidateFileRunsTheMeshStepWithItsSelfIntersectionSwitch) {
  const fs::path file = shared_assets() / "2CylinderEngine/metalrough/2CylinderEngine.gltf";
  ValidateOptions options;
  options.steps = {ValidationStep::Meshes};
  auto count_code = [](const Report& report, const std::string& code) {
    return std::count_if(report.messages.begin(), report.messages.end(),
                         [&](const Issue& issue) { return issue.code == code; });
  };
  const Report with = validate_file(file, "2CylinderEngine.gltf", builtin_rules(), IssuePolicy{}, options);
  EXPECT_EQ(count_code(with, "MESH_TRIANGLE_DEGENERATE"), 25);
  EXPECT_GT(count_code(with, "MESH_SELF_INTERSECTION"), 0);
  options.self_intersections = false;
  const Report without = validate_file(file, "2CylinderEngine.gltf", builtin_rules(), IssuePolicy{}, options);
  EXPECT_EQ(count_code(without, "MESH_TRIANGLE_DEGENERATE"), 25);
  EXPECT_EQ(count_code(without, "MESH_SELF_INTERSECTION"), 0);
}

// ---- Draco ----

TEST(MeshChecks, DracoAssetIsDecodedAndItsDegenerateTrianglesFound) {
  const Asset asset = load_asset(shared_assets() / "2CylinderEngine/metalrough-draco/2CylinderEngine.gltf");
  const long before = work_counters().meshes_decoded;
  const Report report = validate(asset);
  EXPECT_GT(work_counters().meshes_decoded - before, 0);
  for (const Issue& issue : report.messages) EXPECT_NE(issue.code, "MESH_PRIMITIVE_UNREADABLE") << issue.message;
}

// Encodes `mesh` (non-indexed triangle soup positions) with libdraco's sequential encoder into an
// asset using KHR_draco_mesh_compression.
Asset draco_asset(const TestMesh& mesh) {
  draco::TriangleSoupMeshBuilder builder;
  const int faces = static_cast<int>(mesh.indices.size() / 3);
  builder.Start(faces);
  const int position = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  for (int f = 0; f < faces; ++f)
    builder.SetAttributeValuesForFace(position, draco::FaceIndex(f), &mesh.positions[mesh.indices[3 * f]],
                                      &mesh.positions[mesh.indices[3 * f + 1]],
                                      &mesh.positions[mesh.indices[3 * f + 2]]);
  const std::unique_ptr<draco::Mesh> draco_mesh = builder.Finalize();
  draco::Encoder encoder;
  encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
  draco::EncoderBuffer encoded;
  EXPECT_TRUE(encoder.EncodeMeshToBuffer(*draco_mesh, &encoded).ok());

  Asset asset;
  tinygltf::Model& model = asset.model;
  model.buffers.resize(1);
  model.buffers[0].data.assign(encoded.data(), encoded.data() + encoded.size());
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteLength = encoded.size();
  model.bufferViews.push_back(view);
  tinygltf::Accessor positions;  // no bufferView: the data is in the Draco stream
  positions.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  positions.type = TINYGLTF_TYPE_VEC3;
  positions.count = draco_mesh->num_points();
  model.accessors.push_back(positions);
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = 0;
  tinygltf::Value::Object extension;
  extension["bufferView"] = tinygltf::Value(0);
  tinygltf::Value::Object attributes;
  attributes["POSITION"] = tinygltf::Value(static_cast<int>(draco_mesh->attribute(position)->unique_id()));
  extension["attributes"] = tinygltf::Value(attributes);
  primitive.extensions["KHR_draco_mesh_compression"] = tinygltf::Value(extension);
  model.meshes.resize(1);
  model.meshes[0].primitives.push_back(primitive);
  return asset;
}

TEST(MeshChecks, DracoMeshWithCrossingTrianglesIsCaughtAndItsCleanTwinIsNot) {
  const long before = work_counters().meshes_decoded;
  EXPECT_EQ(codes(validate(draco_asset(crossing_triangles(0)))), Codes{"MESH_SELF_INTERSECTION"});
  EXPECT_EQ(codes(validate(draco_asset(crossing_triangles(3)))), Codes{});
  EXPECT_EQ(work_counters().meshes_decoded - before, 2);
}

TEST(MeshChecks, NothingIsDecodedWhenEveryMeshRuleIsOff) {
  RuleSet rules = builtin_rules();
  for (const auto& [code, rule] : builtin_rules().all())
    if (code.starts_with("MESH_")) rules.mutable_rule(code).enabled = false;
  const long before = work_counters().meshes_decoded;
  EXPECT_EQ(codes(validate(draco_asset(crossing_triangles(0)), rules)), Codes{});
  EXPECT_EQ(work_counters().meshes_decoded, before);
}

TEST(MeshChecks, UndecodableDracoDataIsReportedNotIgnored) {
  Asset asset = draco_asset(crossing_triangles(0));
  std::fill(asset.model.buffers[0].data.begin(), asset.model.buffers[0].data.end(), 0xAB);
  const Report report = validate(asset);
  ASSERT_EQ(codes(report), Codes{"MESH_PRIMITIVE_UNREADABLE"});
  EXPECT_NE(report.messages[0].message.find("Draco"), std::string::npos) << report.messages[0].message;
}

// ---- Accessor reading and hostile input ----

TEST(MeshChecks, NonFinitePositionsMakeDegenerateTrianglesNotACrash) {
  TestMesh mesh = cube();
  mesh.positions[0].x = std::numeric_limits<float>::quiet_NaN();
  mesh.positions[5].y = std::numeric_limits<float>::infinity();
  const Report report = validate(make_asset(mesh), all_rules_on());
  ASSERT_FALSE(report.messages.empty());
  EXPECT_EQ(report.messages[0].code, "MESH_TRIANGLE_DEGENERATE");
  EXPECT_NE(report.messages[0].message.find(
                "3 degenerate triangles (repeated vertex position or zero area) out of 12; first: 0, 1, 2."),
            std::string::npos)
      << report.messages[0].message;
}

TEST(MeshChecks, AccessorLargerThanItsBufferSkipsThePrimitiveWithAReason) {
  Asset asset = make_asset(cube());
  asset.model.accessors[0].count = 1'000'000'000'000;  // POSITION
  const Report report = validate(asset);
  ASSERT_EQ(codes(report), Codes{"MESH_PRIMITIVE_UNREADABLE"});
  EXPECT_NE(report.messages[0].message.find("POSITION"), std::string::npos) << report.messages[0].message;
}

TEST(MeshChecks, StridedNormalizedAndSparseAccessorsAreRead) {
  Asset asset = make_asset(crossing_triangles(3));
  tinygltf::Model& model = asset.model;
  // Sparse: move vertex 3 back into the first triangle's plane region so the pair crosses again.
  const std::vector<std::uint32_t> sparse_indices = {3, 4, 5};
  const std::vector<glm::vec3> sparse_values = {{0, -0.5f, -1}, {0, 0.5f, -1}, {0, 0, 1}};
  const int index_accessor =
      append_accessor(model, sparse_indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR);
  const int value_accessor = append_accessor(model, sparse_values, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  tinygltf::Accessor& positions =
      model.accessors[static_cast<std::size_t>(model.meshes[0].primitives[0].attributes["POSITION"])];
  positions.sparse.isSparse = true;
  positions.sparse.count = 3;
  positions.sparse.indices.bufferView = model.accessors[static_cast<std::size_t>(index_accessor)].bufferView;
  positions.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  positions.sparse.indices.byteOffset = 0;  // tinygltf leaves these uninitialized
  positions.sparse.values.byteOffset = 0;
  positions.sparse.values.bufferView = model.accessors[static_cast<std::size_t>(value_accessor)].bufferView;
  const Report sparse_report = validate(asset);
  EXPECT_EQ(codes(sparse_report), Codes{"MESH_SELF_INTERSECTION"})
      << (sparse_report.messages.empty() ? "" : sparse_report.messages[0].message);

  // Normalized signed bytes with a 4-byte stride: 127 reads as 1.0, -127 as -1.0.
  Asset strided = make_asset(quad());
  const std::vector<std::int8_t> normals = {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, -127, 0, 0, 0, -127, 0};
  const int normal_accessor = append_accessor(strided.model, normals, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_TYPE_VEC4);
  strided.model.accessors[static_cast<std::size_t>(normal_accessor)].type = TINYGLTF_TYPE_VEC3;  // 4th byte: padding
  strided.model.accessors[static_cast<std::size_t>(normal_accessor)].normalized = true;
  strided.model.bufferViews.back().byteStride = 4;
  auto& primitive = strided.model.meshes[0].primitives[0];
  primitive.attributes["NORMAL"] = normal_accessor;
  primitive.attributes.erase("TANGENT");
  std::string problem;
  const auto read = mesh::read_triangle_mesh(strided, 0, 0, {true, false, false, false}, problem);
  ASSERT_TRUE(read) << problem;
  ASSERT_EQ(read->normals.size(), 4u);
  EXPECT_EQ(read->normals[1], glm::vec3(0, 0, 1));
  EXPECT_EQ(read->normals[2], glm::vec3(0, 0, -1));
  // Vertices 2 and 3 point down: triangle 1 (0, 2, 3) has two of three against it, not flipped;
  EXPECT_EQ(codes(validate(strided)), Codes{});
}

}  // namespace
}  // namespace gltf_pbr
