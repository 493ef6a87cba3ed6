// The mesh checks' view of one glTF primitive: a triangle soup with the vertex attributes the
// checks read, whatever the primitive's mode or compression. Plus the individual checks, each a
// free function over it, so tests and bench/mesh can run and time them one by one.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/asset.hpp"

namespace gltf_pbr::mesh {

using Triangle = std::array<std::uint32_t, 3>;

struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;   // empty when the primitive has no NORMAL
  std::vector<glm::vec4> tangents;  // empty when the primitive has no TANGENT
  std::vector<glm::vec2> uvs;       // the normal map's texCoord set (else TEXCOORD_0); may be empty
  // Triangles in draw order (strips and fans unrolled, glTF 2.0 section 3.7.2.1), indices into
  // the vertex arrays; a triangle with an index past the vertex arrays is dropped (the structure
  // step reports ACCESSOR_INDEX_OOB) but keeps its number: `triangle_numbers[i]` is the draw-order
  // number of triangles[i], the number messages name.
  std::vector<Triangle> triangles;
  std::vector<std::uint32_t> triangle_numbers;
  // Every attribute of every vertex (all semantics, sorted by name), `signature_stride` floats per
  // vertex, for MESH_VERTEX_DUPLICATE; only filled when asked.
  std::vector<float> vertex_signatures;
  std::size_t signature_stride = 0;
  bool has_normal_map = false;         // the material has a normalTexture, so tangents matter
  bool has_tangent_attribute = false;  // TANGENT present (read or not), so viewers generate none
};

// What the primitive needs read besides positions and indices.
struct MeshReadRequest {
  bool normals = false;
  bool tangents = false;
  bool uvs = false;
  bool vertex_signatures = false;
};

// Triangles of `mode` (TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN) from a vertex sequence. Strip
// triangle i is (i, i+1, i+2) for even i and (i+1, i, i+2) for odd i, so all keep the first's
// winding; fan triangle i is (0, i+1, i+2) (glTF 2.0 section 3.7.2.1).
std::vector<Triangle> triangles_from_sequence(const std::vector<std::uint32_t>& sequence, int mode);

// True for the modes whose primitives have faces.
bool is_triangle_mode(int mode);

// The primitive as a triangle mesh, Draco-decoded when compressed (core/draco.hpp). Returns
// nothing and sets `problem` when its data cannot be read (bad accessor; the structure step
// reports it) or throws InputError when Draco data does not decode.
std::optional<TriangleMesh> read_triangle_mesh(const Asset& asset, int mesh_index, int primitive_index,
                                               const MeshReadRequest& request, std::string& problem);

// ---- The checks. Each returns the offending triangle numbers (or vertex indices), ascending. ----

// Positions merged by exact value: triangles refer to one id per distinct position, so seams
// split for normals or UVs do not look like borders. `welded_triangles[i]` matches
// mesh.triangles[i].
struct WeldedMesh {
  std::vector<std::uint32_t> vertex_to_welded;  // original vertex -> welded id
  std::vector<glm::dvec3> welded_positions;
  std::vector<Triangle> welded_triangles;
  std::vector<bool> triangle_degenerate;  // repeated welded vertex or (near) zero area
  // A later copy of an earlier triangle over the same three welded vertices, either winding.
  std::vector<bool> triangle_duplicate;
  // Degenerate and duplicate triangles are left out of the topology, intersection and attribute
  // checks, so each defect is reported once, by its most specific code.
  bool usable(std::size_t triangle) const { return !triangle_degenerate[triangle] && !triangle_duplicate[triangle]; }
};

struct DegenerateThresholds {
  // |cross(e1, e2)| / longest edge^2 (twice the area over the longest edge squared; sqrt(3)/2 for
  // an equilateral triangle) below this: zero area. 1e-6 sits a decade above float rounding
  // (2^-23 ~ 1.2e-7) of a collinear triple.
  double min_area_ratio = 1e-6;
  double min_edge_ratio = 1e-3;  // shortest / longest edge below this: needle
};

WeldedMesh weld(const TriangleMesh& mesh, const DegenerateThresholds& thresholds);

std::vector<std::uint32_t> find_degenerate_triangles(const TriangleMesh& mesh, const WeldedMesh& welded);
std::vector<std::uint32_t> find_needle_triangles(const TriangleMesh& mesh, const WeldedMesh& welded,
                                                 const DegenerateThresholds& thresholds);
std::vector<std::uint32_t> find_duplicate_triangles(const TriangleMesh& mesh, const WeldedMesh& welded);
std::vector<std::uint32_t> find_duplicate_vertices(const TriangleMesh& mesh);

// Edge and vertex topology over the welded mesh, degenerate triangles left out.
struct TopologyFindings {
  std::vector<std::uint32_t> non_manifold_edge_triangles;  // a triangle on each edge with > 2 faces
  std::size_t non_manifold_edges = 0;
  std::vector<std::uint32_t> border_edge_triangles;  // the triangle on each edge with 1 face
  std::size_t border_edges = 0;
  std::vector<std::uint32_t> inconsistent_winding_triangles;  // the second triangle on each such edge
  std::size_t inconsistent_winding_edges = 0;
  std::vector<std::uint32_t> non_manifold_vertices;  // original vertex indices, one per welded vertex
};
struct TopologyRequest {
  bool non_manifold_edges = true, border_edges = true, winding = true, non_manifold_vertices = true;
};
TopologyFindings analyse_topology(const TriangleMesh& mesh, const WeldedMesh& welded, const TopologyRequest& request);

// Pairs of triangles (draw-order numbers) that intersect other than in a shared vertex or edge;
// at most `max_pairs` of them (the search stops there). CGAL, in self_intersections.cpp.
struct SelfIntersections {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  bool stopped_at_limit = false;
};
SelfIntersections find_self_intersections(const TriangleMesh& mesh, const WeldedMesh& welded, std::size_t max_pairs);

// Triangles whose three vertex normals all point more than `max_angle_degrees` away from the
// geometric normal (counter-clockwise winding, glTF 2.0 section 3.7.2.1).
std::vector<std::uint32_t> find_flipped_normals(const TriangleMesh& mesh, const WeldedMesh& welded,
                                                double max_angle_degrees);
// Vertices whose tangent makes |cos| > max_abs_cosine with the normal.
std::vector<std::uint32_t> find_non_orthogonal_tangents(const TriangleMesh& mesh, double max_abs_cosine);
// Vertices whose tangent w disagrees with the handedness every incident triangle's UVs give.
std::vector<std::uint32_t> find_wrong_handedness(const TriangleMesh& mesh, const WeldedMesh& welded);
// Triangles with zero UV area relative to their UV extent (tangent frames undefined there).
std::vector<std::uint32_t> find_degenerate_uv_triangles(const TriangleMesh& mesh, const WeldedMesh& welded,
                                                        double min_uv_area_ratio);

}  // namespace gltf_pbr::mesh
