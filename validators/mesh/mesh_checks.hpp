// Mesh checks (MESH_* codes, rules/mesh.json) on every triangle primitive, Draco included. CGAL
// stays inside this folder's .cpp files: it costs ~19 s and 740 MB to compile one of them.
#pragma once
#include <cstddef>

#include "core/asset.hpp"
#include "core/report.hpp"
#include "rules/rule_set.hpp"

namespace gltf_pbr {

struct MeshCheckOptions {
  bool self_intersections = true;  // the costliest check; switchable
  std::size_t listed_indices = 5;  // triangle or vertex indices each folded message names
};

// One message per code per primitive (pointer /meshes/M/primitives/P) with the count and the
// first `listed_indices` triangle or vertex indices. Reads nothing when no MESH_* rule is enabled
// or no primitive has triangles; decodes a Draco primitive only when it is checked.
void validate_meshes(const Asset& asset, const RuleSet& rules, const MeshCheckOptions& options, Report& report);

}  // namespace gltf_pbr
