#include "validators/mesh/mesh_checks.hpp"

#include <new>
#include <sstream>
#include <string_view>

#include "core/error.hpp"
#include "rules/issue_sink.hpp"
#include "validators/mesh/triangle_mesh.hpp"

namespace gltf_pbr {

namespace {

std::string format_number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string first_indices(const std::vector<std::uint32_t>& indices, std::size_t listed) {
  std::string text;
  for (std::size_t i = 0; i < indices.size() && i < listed; ++i) text += (i ? ", " : "") + std::to_string(indices[i]);
  if (indices.size() > listed) text += ", ...";
  return text;
}

class PrimitiveReporter {
 public:
  PrimitiveReporter(const RuleSet& rules, Report& report, std::string pointer, std::size_t listed)
      : rules_(rules), report_(report), pointer_(std::move(pointer)), listed_(listed) {}

  // {0} count, {1} total, {2} first indices, {3} the rule's threshold named `threshold`.
  void add(const std::string& code, std::size_t count, std::size_t total, const std::string& listed_text,
           const std::string& threshold = "") const {
    if (count == 0) return;
    const std::string threshold_text = threshold.empty() ? "" : format_number(rules_.at(code).threshold(threshold));
    IssueSink(rules_, report_)
        .at_text(code, pointer_, {std::to_string(count), std::to_string(total), listed_text, threshold_text});
  }
  void add(const std::string& code, const std::vector<std::uint32_t>& indices, std::size_t total,
           const std::string& threshold = "") const {
    add(code, indices.size(), total, first_indices(indices, listed_), threshold);
  }
  void add_text(const std::string& code, const std::string& text) const {
    IssueSink(rules_, report_).at_text(code, pointer_, {text});
  }

 private:
  const RuleSet& rules_;
  Report& report_;
  std::string pointer_;
  std::size_t listed_;
};

struct EnabledChecks {
  bool degenerate, needle, duplicate_triangles, duplicate_vertices, non_manifold_edges, non_manifold_vertices,
      border_edges, winding, self_intersections, flipped_normals, tangent_orthogonality, tangent_handedness,
      uv_degenerate;
  bool any() const {
    return degenerate || needle || duplicate_triangles || duplicate_vertices || non_manifold_edges ||
           non_manifold_vertices || border_edges || winding || self_intersections || flipped_normals ||
           tangent_orthogonality || tangent_handedness || uv_degenerate;
  }
  bool topology() const { return non_manifold_edges || non_manifold_vertices || border_edges || winding; }
};

void check_primitive(const Asset& asset, int mesh_index, int primitive_index, const RuleSet& rules,
                     const EnabledChecks& enabled, const MeshCheckOptions& options, Report& report) {
  const std::string where = pointer("meshes", mesh_index) + pointer("primitives", primitive_index);
  const PrimitiveReporter reporter(rules, report, where, options.listed_indices);

  mesh::MeshReadRequest request;
  request.normals = enabled.flipped_normals || enabled.tangent_orthogonality || enabled.tangent_handedness;
  request.tangents = enabled.tangent_orthogonality || enabled.tangent_handedness;
  request.uvs = enabled.tangent_handedness || enabled.uv_degenerate;
  request.vertex_signatures = enabled.duplicate_vertices;
  std::string problem;
  std::optional<mesh::TriangleMesh> read;
  try {
    read = mesh::read_triangle_mesh(asset, mesh_index, primitive_index, request, problem);
  } catch (const InputError& error) {
    problem = error.reason;
  } catch (const std::bad_alloc&) {
    // Counts that the buffers do not back are rejected before allocating; this is for a real
    // primitive larger than memory, which must not take the whole report down.
    problem = "not enough memory to read it";
  }
  if (!read) {
    if (rules.enabled("MESH_PRIMITIVE_UNREADABLE")) reporter.add_text("MESH_PRIMITIVE_UNREADABLE", problem);
    return;
  }
  const mesh::TriangleMesh& mesh = *read;
  const std::size_t triangle_count = mesh.triangles.size();
  const std::size_t vertex_count = mesh.positions.size();

  mesh::DegenerateThresholds thresholds;
  if (const Rule* rule = rules.find("MESH_TRIANGLE_DEGENERATE"))
    thresholds.min_area_ratio = rule->threshold("min_area_ratio");
  if (const Rule* rule = rules.find("MESH_TRIANGLE_NEEDLE"))
    thresholds.min_edge_ratio = rule->threshold("min_edge_ratio");
  const mesh::WeldedMesh welded = mesh::weld(mesh, thresholds);

  if (enabled.degenerate)
    reporter.add("MESH_TRIANGLE_DEGENERATE", mesh::find_degenerate_triangles(mesh, welded), triangle_count);
  if (enabled.needle)
    reporter.add("MESH_TRIANGLE_NEEDLE", mesh::find_needle_triangles(mesh, welded, thresholds), triangle_count,
                 "min_edge_ratio");
  if (enabled.duplicate_triangles)
    reporter.add("MESH_TRIANGLE_DUPLICATE", mesh::find_duplicate_triangles(mesh, welded), triangle_count);
  if (enabled.duplicate_vertices)
    reporter.add("MESH_VERTEX_DUPLICATE", mesh::find_duplicate_vertices(mesh), vertex_count);

  if (enabled.topology()) {
    const mesh::TopologyFindings topology = mesh::analyse_topology(
        mesh, welded,
        {enabled.non_manifold_edges, enabled.border_edges, enabled.winding, enabled.non_manifold_vertices});
    if (enabled.non_manifold_edges)
      reporter.add("MESH_EDGE_NON_MANIFOLD", topology.non_manifold_edges, triangle_count,
                   first_indices(topology.non_manifold_edge_triangles, options.listed_indices));
    if (enabled.non_manifold_vertices)
      reporter.add("MESH_VERTEX_NON_MANIFOLD", topology.non_manifold_vertices, vertex_count);
    if (enabled.border_edges)
      reporter.add("MESH_EDGE_BORDER", topology.border_edges, triangle_count,
                   first_indices(topology.border_edge_triangles, options.listed_indices));
    if (enabled.winding)
      reporter.add("MESH_WINDING_INCONSISTENT", topology.inconsistent_winding_edges, triangle_count,
                   first_indices(topology.inconsistent_winding_triangles, options.listed_indices));
  }

  if (enabled.self_intersections) {
    const auto max_pairs = static_cast<std::size_t>(rules.at("MESH_SELF_INTERSECTION").threshold("max_pairs"));
    const mesh::SelfIntersections found = mesh::find_self_intersections(mesh, welded, max_pairs);
    std::string pairs;
    for (std::size_t i = 0; i < found.pairs.size() && i < options.listed_indices; ++i)
      pairs += (i ? ", " : "") + std::to_string(found.pairs[i].first) + "/" + std::to_string(found.pairs[i].second);
    if (found.pairs.size() > options.listed_indices) pairs += ", ...";
    if (!found.pairs.empty()) {
      const std::string count = (found.stopped_at_limit ? "At least " : "") + std::to_string(found.pairs.size());
      IssueSink(rules, report).at_text("MESH_SELF_INTERSECTION", where, {count, std::to_string(triangle_count), pairs});
    }
  }

  if (enabled.flipped_normals)
    reporter.add(
        "MESH_NORMAL_FLIPPED",
        mesh::find_flipped_normals(mesh, welded, rules.at("MESH_NORMAL_FLIPPED").threshold("max_angle_degrees")),
        triangle_count, "max_angle_degrees");
  if (enabled.tangent_orthogonality)
    reporter.add(
        "MESH_TANGENT_NOT_ORTHOGONAL",
        mesh::find_non_orthogonal_tangents(mesh, rules.at("MESH_TANGENT_NOT_ORTHOGONAL").threshold("max_abs_cosine")),
        vertex_count, "max_abs_cosine");
  if (enabled.tangent_handedness)
    reporter.add("MESH_TANGENT_HANDEDNESS", mesh::find_wrong_handedness(mesh, welded), vertex_count);
  // Zero UV area matters where the viewer must generate tangents: a normal map and no TANGENT.
  if (enabled.uv_degenerate && mesh.has_normal_map && !mesh.has_tangent_attribute)
    reporter.add(
        "MESH_UV_DEGENERATE",
        mesh::find_degenerate_uv_triangles(mesh, welded, rules.at("MESH_UV_DEGENERATE").threshold("min_uv_area_ratio")),
        triangle_count);
}

}  // namespace

void validate_meshes(const Asset& asset, const RuleSet& rules, const MeshCheckOptions& options, Report& report) {
  EnabledChecks enabled{};
  enabled.degenerate = rules.enabled("MESH_TRIANGLE_DEGENERATE");
  enabled.needle = rules.enabled("MESH_TRIANGLE_NEEDLE");
  enabled.duplicate_triangles = rules.enabled("MESH_TRIANGLE_DUPLICATE");
  enabled.duplicate_vertices = rules.enabled("MESH_VERTEX_DUPLICATE");
  enabled.non_manifold_edges = rules.enabled("MESH_EDGE_NON_MANIFOLD");
  enabled.non_manifold_vertices = rules.enabled("MESH_VERTEX_NON_MANIFOLD");
  enabled.border_edges = rules.enabled("MESH_EDGE_BORDER");
  enabled.winding = rules.enabled("MESH_WINDING_INCONSISTENT");
  enabled.self_intersections = options.self_intersections && rules.enabled("MESH_SELF_INTERSECTION");
  enabled.flipped_normals = rules.enabled("MESH_NORMAL_FLIPPED");
  enabled.tangent_orthogonality = rules.enabled("MESH_TANGENT_NOT_ORTHOGONAL");
  enabled.tangent_handedness = rules.enabled("MESH_TANGENT_HANDEDNESS");
  enabled.uv_degenerate = rules.enabled("MESH_UV_DEGENERATE");
  if (!enabled.any()) return;
  const auto& meshes = asset.model.meshes;
  for (std::size_t m = 0; m < meshes.size(); ++m)
    for (std::size_t p = 0; p < meshes[m].primitives.size(); ++p)
      if (mesh::is_triangle_mode(meshes[m].primitives[p].mode))
        check_primitive(asset, static_cast<int>(m), static_cast<int>(p), rules, enabled, options, report);
}

}  // namespace gltf_pbr
