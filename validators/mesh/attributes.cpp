// Checks of vertex attributes against the geometry: normals, tangents, and the UVs that tangent
// generation needs.
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "validators/mesh/triangle_mesh.hpp"

namespace gltf_pbr::mesh {

namespace {

glm::dvec3 geometric_normal(const WeldedMesh& welded, std::size_t triangle) {
  const Triangle& w = welded.welded_triangles[triangle];
  const glm::dvec3 a = welded.welded_positions[w[0]], b = welded.welded_positions[w[1]],
                   c = welded.welded_positions[w[2]];
  return glm::normalize(glm::cross(b - a, c - a));  // counter-clockwise front (glTF 2.0 section 3.7.2.1)
}

// Twice the signed UV area of a triangle and its longest UV edge squared.
struct UvShape {
  double signed_double_area = 0, longest_squared = 0;
};
UvShape uv_shape(const TriangleMesh& mesh, const Triangle& triangle) {
  const glm::dvec2 a = mesh.uvs[triangle[0]], b = mesh.uvs[triangle[1]], c = mesh.uvs[triangle[2]];
  const glm::dvec2 e1 = b - a, e2 = c - a, e3 = c - b;
  return {e1.x * e2.y - e2.x * e1.y, std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)})};
}

}  // namespace

std::vector<std::uint32_t> find_flipped_normals(const TriangleMesh& mesh, const WeldedMesh& welded,
                                                double max_angle_degrees) {
  std::vector<std::uint32_t> numbers;
  if (mesh.normals.empty()) return numbers;
  const double min_cosine = std::cos(max_angle_degrees * std::numbers::pi / 180.0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!welded.usable(t)) continue;
    const glm::dvec3 face = geometric_normal(welded, t);
    // Flipped only when every corner's normal disagrees: one corner past the limit is a crease
    // or a smoothing choice, three are a triangle wound against its normals.
    bool all_away = true;
    for (std::uint32_t vertex : mesh.triangles[t]) {
      const glm::dvec3 normal = mesh.normals[vertex];
      const double length = glm::length(normal);
      if (!(length > 0) || glm::dot(face, normal) / length >= min_cosine) {
        all_away = false;
        break;
      }
    }
    if (all_away) numbers.push_back(mesh.triangle_numbers[t]);
  }
  return numbers;
}

std::vector<std::uint32_t> find_non_orthogonal_tangents(const TriangleMesh& mesh, double max_abs_cosine) {
  std::vector<std::uint32_t> vertices;
  if (mesh.normals.empty() || mesh.tangents.empty()) return vertices;
  for (std::size_t v = 0; v < mesh.tangents.size(); ++v) {
    const glm::dvec3 normal = mesh.normals[v], tangent = glm::dvec3(mesh.tangents[v]);
    const double lengths = glm::length(normal) * glm::length(tangent);
    if (!(lengths > 0)) continue;  // zero vectors: the structure step's ACCESSOR_VECTOR3_NON_UNIT
    if (std::abs(glm::dot(normal, tangent)) / lengths > max_abs_cosine)
      vertices.push_back(static_cast<std::uint32_t>(v));
  }
  return vertices;
}

std::vector<std::uint32_t> find_wrong_handedness(const TriangleMesh& mesh, const WeldedMesh& welded) {
  std::vector<std::uint32_t> vertices;
  if (mesh.tangents.empty() || mesh.uvs.empty()) return vertices;
  // Per vertex: how many incident triangles' UVs ask for w = +1 and for w = -1.
  std::vector<std::uint32_t> positive(mesh.tangents.size(), 0), negative(mesh.tangents.size(), 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!welded.usable(t)) continue;
    const Triangle& triangle = mesh.triangles[t];
    const UvShape uv = uv_shape(mesh, triangle);
    if (!(std::abs(uv.signed_double_area) > 1e-12 * uv.longest_squared)) continue;  // no UV frame here
    // Tangent and bitangent along +u and +v (Lengyel, "Computing Tangent Space Basis Vectors for
    // an Arbitrary Mesh", 2001).
    const glm::dvec3 p0 = mesh.positions[triangle[0]], p1 = mesh.positions[triangle[1]],
                     p2 = mesh.positions[triangle[2]];
    const glm::dvec2 t0 = mesh.uvs[triangle[0]], t1 = mesh.uvs[triangle[1]], t2 = mesh.uvs[triangle[2]];
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::dvec2 d1 = t1 - t0, d2 = t2 - t0;
    const double r = 1.0 / uv.signed_double_area;
    const glm::dvec3 along_u = (e1 * d2.y - e2 * d1.y) * r;
    const glm::dvec3 along_v = (e2 * d1.x - e1 * d2.x) * r;
    // glTF's UV origin is the image's top-left (glTF 2.0, "Texture Data") and a normal map's +Y
    // points up the image (material.normalTexture), so the bitangent runs along -v; and
    // bitangent = cross(normal, tangent.xyz) * tangent.w (glTF 2.0, "Meshes", TANGENT).
    for (std::uint32_t vertex : triangle) {
      const glm::dvec3 normal = mesh.normals.empty() ? geometric_normal(welded, t) : glm::dvec3(mesh.normals[vertex]);
      const double side = glm::dot(glm::cross(normal, along_u), -along_v);
      if (side > 0) ++positive[vertex];
      if (side < 0) ++negative[vertex];
    }
  }
  for (std::size_t v = 0; v < mesh.tangents.size(); ++v) {
    const float w = mesh.tangents[v].w;
    // Vertices on a mirror seam get both answers: ambiguous, left alone.
    if ((w > 0 && negative[v] > 0 && positive[v] == 0) || (w < 0 && positive[v] > 0 && negative[v] == 0))
      vertices.push_back(static_cast<std::uint32_t>(v));
  }
  return vertices;
}

std::vector<std::uint32_t> find_degenerate_uv_triangles(const TriangleMesh& mesh, const WeldedMesh& welded,
                                                        double min_uv_area_ratio) {
  std::vector<std::uint32_t> numbers;
  if (mesh.uvs.empty()) return numbers;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!welded.usable(t)) continue;
    const UvShape uv = uv_shape(mesh, mesh.triangles[t]);
    // MikkTSpace (and every tangent generator) divides by this area: at zero the tangent frame
    // is undefined and the normal map shades the triangle arbitrarily.
    if (!(std::abs(uv.signed_double_area) >= min_uv_area_ratio * uv.longest_squared) || uv.longest_squared == 0)
      numbers.push_back(mesh.triangle_numbers[t]);
  }
  return numbers;
}

}  // namespace gltf_pbr::mesh
