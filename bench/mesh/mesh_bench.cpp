// Times each mesh check separately, with peak memory, on VC, 2CylinderEngine (../shared/assets)
// and a generated 1M-triangle height field. Every measurement runs in a forked child so its peak
// resident set (getrusage ru_maxrss of the child) is its own: load + read + weld + that check.
//   mesh-bench [asset.gltf ...]      (no arguments: the three inputs above)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "core/accessor.hpp"
#include "core/asset.hpp"
#include "rules/rule_set.hpp"
#include "validators/mesh/mesh_checks.hpp"
#include "validators/mesh/triangle_mesh.hpp"

using namespace gltf_pbr;

namespace {

struct Input {
  std::string name;
  std::string path;  // empty: the generated height field
};

struct Prepared {
  std::vector<mesh::TriangleMesh> meshes;
  std::vector<mesh::WeldedMesh> welded;
  std::size_t triangles = 0;
};

// A wavy height field of 2 * side^2 triangles: no intersections, every edge manifold, so the
// checks do their full work without reporting.
mesh::TriangleMesh height_field(std::uint32_t side) {
  mesh::TriangleMesh mesh;
  const std::uint32_t n = side + 1;
  for (std::uint32_t y = 0; y < n; ++y)
    for (std::uint32_t x = 0; x < n; ++x) {
      const float u = static_cast<float>(x) / side, v = static_cast<float>(y) / side;
      mesh.positions.push_back({u, v, 0.05f * std::sin(20.0f * u) * std::cos(17.0f * v)});
      mesh.normals.push_back({0, 0, 1});
      mesh.tangents.push_back({1, 0, 0, 1});
      mesh.uvs.push_back({u, 1.0f - v});
    }
  for (std::uint32_t y = 0; y < side; ++y)
    for (std::uint32_t x = 0; x < side; ++x) {
      const std::uint32_t a = y * n + x, b = a + 1, c = a + n, d = c + 1;
      mesh.triangles.push_back({a, b, d});
      mesh.triangles.push_back({a, d, c});
    }
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) mesh.triangle_numbers.push_back(t);
  mesh.signature_stride = 12;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const float values[12] = {mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z, mesh.normals[v].x,
                              mesh.normals[v].y,   mesh.normals[v].z,   mesh.tangents[v].x,  mesh.tangents[v].y,
                              mesh.tangents[v].z,  mesh.tangents[v].w,  mesh.uvs[v].x,       mesh.uvs[v].y};
    mesh.vertex_signatures.insert(mesh.vertex_signatures.end(), values, values + 12);
  }
  return mesh;
}

// The height field as an in-memory glTF asset (float attributes, 32-bit indices, a normal map),
// so validate_meshes runs on it end to end as on a loaded file.
Asset height_field_asset(const mesh::TriangleMesh& field) {
  Asset asset;
  tinygltf::Model& model = asset.model;
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.attributes["POSITION"] =
      append_accessor(model, field.positions, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  primitive.attributes["NORMAL"] =
      append_accessor(model, field.normals, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  primitive.attributes["TANGENT"] =
      append_accessor(model, field.tangents, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4);
  primitive.attributes["TEXCOORD_0"] =
      append_accessor(model, field.uvs, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2);
  primitive.indices =  // three indices per triangle: the count comes from the byte size
      append_accessor(model, field.triangles, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR);
  model.images.resize(1);
  model.textures.resize(1);
  model.textures[0].source = 0;
  model.materials.resize(1);
  model.materials[0].normalTexture.index = 0;
  primitive.material = 0;
  model.meshes.resize(1);
  model.meshes[0].primitives.push_back(primitive);
  return asset;
}

Prepared prepare(const Input& input, const mesh::DegenerateThresholds& thresholds) {
  Prepared prepared;
  if (input.path.empty()) {
    prepared.meshes.push_back(height_field(708));
  } else {
    const Asset asset = load_asset(input.path);
    const mesh::MeshReadRequest everything{true, true, true, true};
    for (std::size_t m = 0; m < asset.model.meshes.size(); ++m)
      for (std::size_t p = 0; p < asset.model.meshes[m].primitives.size(); ++p) {
        if (!mesh::is_triangle_mode(asset.model.meshes[m].primitives[p].mode)) continue;
        std::string problem;
        auto read = mesh::read_triangle_mesh(asset, static_cast<int>(m), static_cast<int>(p), everything, problem);
        if (read) prepared.meshes.push_back(std::move(*read));
      }
  }
  for (const auto& triangle_mesh : prepared.meshes) {
    prepared.welded.push_back(mesh::weld(triangle_mesh, thresholds));
    prepared.triangles += triangle_mesh.triangles.size();
  }
  return prepared;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Runs `body` in a child; prints its wall time (measured in the child) and the child's peak RSS.
void measure(const std::string& input, const std::string& step, const std::function<double()>& body) {
  int channel[2];
  if (pipe(channel) != 0) return;
  const pid_t child = fork();
  if (child == 0) {
    close(channel[0]);
    const double seconds = body();
    if (write(channel[1], &seconds, sizeof seconds) != sizeof seconds) _exit(1);
    _exit(0);
  }
  close(channel[1]);
  double seconds = -1;
  if (read(channel[0], &seconds, sizeof seconds) != sizeof seconds) seconds = -1;
  close(channel[0]);
  int status = 0;
  rusage usage{};
  wait4(child, &status, 0, &usage);
  std::printf("%-16s %-28s %9.3f s %8.1f MB\n", input.c_str(), step.c_str(), seconds, usage.ru_maxrss / 1024.0);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<Input> inputs;
  for (int i = 1; i < argc; ++i) inputs.push_back({argv[i], argv[i]});
  if (inputs.empty()) {
    const std::string assets = std::string(GLTF_PBR_SHARED_DIR) + "/assets/";
    inputs = {{"VC", assets + "VC/metalrough/VC.gltf"},
              {"2CylinderEngine", assets + "2CylinderEngine/metalrough/2CylinderEngine.gltf"},
              {"2CylEngine-draco", assets + "2CylinderEngine/metalrough-draco/2CylinderEngine.gltf"},
              {"heightfield-1M", ""}};
  }
  const RuleSet& rules = builtin_rules();
  const mesh::DegenerateThresholds thresholds{rules.at("MESH_TRIANGLE_DEGENERATE").threshold("min_area_ratio"),
                                              rules.at("MESH_TRIANGLE_NEEDLE").threshold("min_edge_ratio")};
  std::printf("%-16s %-28s %11s %11s\n", "input", "step", "time", "peak RSS");
  for (const Input& input : inputs) {
    using Check = std::function<void(const mesh::TriangleMesh&, const mesh::WeldedMesh&)>;
    const std::vector<std::pair<std::string, Check>> checks = {
        {"degenerate", [](auto& m, auto& w) { mesh::find_degenerate_triangles(m, w); }},
        {"needle", [&](auto& m, auto& w) { mesh::find_needle_triangles(m, w, thresholds); }},
        {"duplicate triangles", [](auto& m, auto& w) { mesh::find_duplicate_triangles(m, w); }},
        {"duplicate vertices", [](auto& m, auto&) { mesh::find_duplicate_vertices(m); }},
        {"topology (edges, vertices)", [](auto& m, auto& w) { mesh::analyse_topology(m, w, {}); }},
        {"self-intersections (CGAL)", [](auto& m, auto& w) { mesh::find_self_intersections(m, w, 1000); }},
        {"flipped normals", [](auto& m, auto& w) { mesh::find_flipped_normals(m, w, 90); }},
        {"tangent orthogonality", [](auto& m, auto&) { mesh::find_non_orthogonal_tangents(m, 0.1); }},
        {"tangent handedness", [](auto& m, auto& w) { mesh::find_wrong_handedness(m, w); }},
        {"UV degenerate", [](auto& m, auto& w) { mesh::find_degenerate_uv_triangles(m, w, 1e-6); }},
    };
    measure(input.name, "read + weld (baseline)", [&] {
      const auto start = std::chrono::steady_clock::now();
      const Prepared prepared = prepare(input, thresholds);
      std::printf("%-16s %zu primitives, %zu triangles\n", input.name.c_str(), prepared.meshes.size(),
                  prepared.triangles);
      return seconds_since(start);
    });
    for (const auto& [name, check] : checks)
      measure(input.name, name, [&, &check = check] {
        const Prepared prepared = prepare(input, thresholds);
        const auto start = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i < prepared.meshes.size(); ++i) check(prepared.meshes[i], prepared.welded[i]);
        return seconds_since(start);
      });
    measure(input.name, input.path.empty() ? "validate_meshes (all)" : "validate_meshes (all, load)", [&] {
      const Asset asset = input.path.empty() ? height_field_asset(height_field(708)) : Asset{};
      const auto start = std::chrono::steady_clock::now();
      const Asset loaded = input.path.empty() ? Asset{} : load_asset(input.path);
      Report report;
      validate_meshes(input.path.empty() ? asset : loaded, rules, MeshCheckOptions{}, report);
      return seconds_since(start);
    });
  }
  return 0;
}
