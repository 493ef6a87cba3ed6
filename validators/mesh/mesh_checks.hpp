// Mesh checks (MESH_* codes, rules/mesh.json) on every triangle primitive, Draco included. CGAL
// stays inside this folder's .cpp files: it costs ~19 s and 740 MB to compile one of them.
#pragma once
#include "core/asset.hpp"
#include "core/report.hpp"
#include "rules/rule_set.hpp"

namespace gltf_pbr {

struct MeshCheckOptions {
  bool self_intersections = true;  // the costliest check; switchable
};

void validate_meshes(const Asset& asset, const RuleSet& rules, const MeshCheckOptions& options, Report& report);

}  // namespace gltf_pbr
