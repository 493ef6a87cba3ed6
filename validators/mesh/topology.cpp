// Welding, degenerate/needle/duplicate triangles, duplicate vertices and edge/vertex topology.
// Plain sorting instead of CGAL's halfedge structures: a glTF primitive may be non-manifold or
// inconsistently wound, which a Surface_mesh cannot even hold, and these are the defects sought.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <numeric>
#include <tuple>

#include "validators/mesh/triangle_mesh.hpp"

namespace gltf_pbr::mesh {

namespace {

// A float's bits with -0.0 folded into +0.0: a total order, so NaN (which the structure step
// reports as ACCESSOR_INVALID_FLOAT) cannot break std::sort's strict weak ordering.
std::uint32_t ordered_bits(float value) { return std::bit_cast<std::uint32_t>(value + 0.0f); }

struct TriangleShape {
  double cross_length = 0;  // |cross(e1, e2)|, twice the area
  double shortest = 0, longest = 0;
};

TriangleShape shape(const WeldedMesh& welded, const Triangle& triangle) {
  const glm::dvec3 a = welded.welded_positions[triangle[0]], b = welded.welded_positions[triangle[1]],
                   c = welded.welded_positions[triangle[2]];
  const double ab = glm::length(b - a), bc = glm::length(c - b), ca = glm::length(a - c);
  return {glm::length(glm::cross(b - a, c - a)), std::min({ab, bc, ca}), std::max({ab, bc, ca})};
}

std::vector<std::uint32_t> numbers_where(const TriangleMesh& mesh, const std::vector<bool>& flags) {
  std::vector<std::uint32_t> numbers;
  for (std::size_t t = 0; t < flags.size(); ++t)
    if (flags[t]) numbers.push_back(mesh.triangle_numbers[t]);
  return numbers;
}

// Union-find over triangle corners (3 * triangle + k), path halving.
struct DisjointSets {
  std::vector<std::uint32_t> parent;
  explicit DisjointSets(std::size_t size) : parent(size) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

}  // namespace

WeldedMesh weld(const TriangleMesh& mesh, const DegenerateThresholds& thresholds) {
  WeldedMesh welded;
  const std::size_t vertex_count = mesh.positions.size();
  std::vector<std::uint32_t> order(vertex_count);
  std::iota(order.begin(), order.end(), 0u);
  auto less = [&](std::uint32_t i, std::uint32_t j) {
    const glm::vec3 a = mesh.positions[i], b = mesh.positions[j];
    return std::tuple(ordered_bits(a.x), ordered_bits(a.y), ordered_bits(a.z)) <
           std::tuple(ordered_bits(b.x), ordered_bits(b.y), ordered_bits(b.z));
  };
  std::sort(order.begin(), order.end(), less);
  welded.vertex_to_welded.resize(vertex_count);
  for (std::size_t k = 0; k < vertex_count; ++k) {
    if (k == 0 || less(order[k - 1], order[k])) welded.welded_positions.push_back(glm::dvec3(mesh.positions[order[k]]));
    welded.vertex_to_welded[order[k]] = static_cast<std::uint32_t>(welded.welded_positions.size() - 1);
  }

  const std::size_t triangle_count = mesh.triangles.size();
  welded.welded_triangles.resize(triangle_count);
  welded.triangle_degenerate.assign(triangle_count, false);
  welded.triangle_duplicate.assign(triangle_count, false);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    Triangle& w = welded.welded_triangles[t];
    for (int k = 0; k < 3; ++k) w[k] = welded.vertex_to_welded[mesh.triangles[t][k]];
    if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) {
      welded.triangle_degenerate[t] = true;
      continue;
    }
    // Non-finite corners count as degenerate: no plane, and nothing later may see them.
    const TriangleShape s = shape(welded, w);
    welded.triangle_degenerate[t] = !std::isfinite(s.cross_length) || !std::isfinite(s.longest) ||
                                    !(s.cross_length >= thresholds.min_area_ratio * s.longest * s.longest);
  }

  // Duplicates: the same welded vertex set, either winding; the first occurrence is kept.
  std::vector<std::pair<Triangle, std::uint32_t>> sorted_sets;
  sorted_sets.reserve(triangle_count);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    if (welded.triangle_degenerate[t]) continue;
    Triangle key = welded.welded_triangles[t];
    std::sort(key.begin(), key.end());
    sorted_sets.push_back({key, static_cast<std::uint32_t>(t)});
  }
  std::sort(sorted_sets.begin(), sorted_sets.end());
  for (std::size_t k = 1; k < sorted_sets.size(); ++k)
    if (sorted_sets[k].first == sorted_sets[k - 1].first) welded.triangle_duplicate[sorted_sets[k].second] = true;
  return welded;
}

std::vector<std::uint32_t> find_degenerate_triangles(const TriangleMesh& mesh, const WeldedMesh& welded) {
  return numbers_where(mesh, welded.triangle_degenerate);
}

std::vector<std::uint32_t> find_needle_triangles(const TriangleMesh& mesh, const WeldedMesh& welded,
                                                 const DegenerateThresholds& thresholds) {
  std::vector<std::uint32_t> numbers;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (welded.triangle_degenerate[t]) continue;
    const TriangleShape s = shape(welded, welded.welded_triangles[t]);
    if (s.shortest < thresholds.min_edge_ratio * s.longest) numbers.push_back(mesh.triangle_numbers[t]);
  }
  return numbers;
}

std::vector<std::uint32_t> find_duplicate_triangles(const TriangleMesh& mesh, const WeldedMesh& welded) {
  return numbers_where(mesh, welded.triangle_duplicate);
}

std::vector<std::uint32_t> find_duplicate_vertices(const TriangleMesh& mesh) {
  // Vertices equal in every attribute could share one index (what gltfpack/meshoptimizer's
  // remap does); a position shared at a UV or normal seam is not a duplicate.
  const std::size_t stride = mesh.signature_stride;
  const std::size_t vertex_count = stride ? mesh.vertex_signatures.size() / stride : 0;
  auto signature = [&](std::uint32_t v) { return mesh.vertex_signatures.data() + v * stride; };
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    const float *x = signature(a), *y = signature(b);
    for (std::size_t c = 0; c < stride; ++c)
      if (ordered_bits(x[c]) != ordered_bits(y[c])) return ordered_bits(x[c]) < ordered_bits(y[c]);
    return a < b;
  };
  auto same = [&](std::uint32_t a, std::uint32_t b) {
    return std::equal(signature(a), signature(a) + stride, signature(b),
                      [](float x, float y) { return ordered_bits(x) == ordered_bits(y); });
  };
  std::vector<std::uint32_t> order(vertex_count);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), less);
  std::vector<std::uint32_t> duplicates;
  for (std::size_t k = 1; k < vertex_count; ++k)
    if (same(order[k - 1], order[k])) duplicates.push_back(order[k]);  // the higher index of each equal run
  std::sort(duplicates.begin(), duplicates.end());
  return duplicates;
}

TopologyFindings analyse_topology(const TriangleMesh& mesh, const WeldedMesh& welded, const TopologyRequest& request) {
  TopologyFindings findings;
  struct EdgeUse {
    std::uint64_t key;  // (smaller welded id << 32) | larger
    std::uint32_t triangle;
    std::uint8_t corner;  // the edge runs from corner to corner + 1 (mod 3)
    bool forward;         // from the smaller id to the larger
  };
  std::vector<EdgeUse> uses;
  uses.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!welded.usable(t)) continue;
    const Triangle& w = welded.welded_triangles[t];
    for (std::uint8_t k = 0; k < 3; ++k) {
      const std::uint32_t from = w[k], to = w[(k + 1) % 3];
      const std::uint64_t key = (std::uint64_t{std::min(from, to)} << 32) | std::max(from, to);
      uses.push_back({key, static_cast<std::uint32_t>(t), k, from < to});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& a, const EdgeUse& b) {
    return std::tie(a.key, a.triangle, a.corner) < std::tie(b.key, b.triangle, b.corner);
  });

  DisjointSets corners(request.non_manifold_vertices ? mesh.triangles.size() * 3 : 0);
  std::vector<bool> on_non_manifold_edge(request.non_manifold_vertices ? welded.welded_positions.size() : 0, false);
  for (std::size_t begin = 0, end = 0; begin < uses.size(); begin = end) {
    end = begin + 1;
    while (end < uses.size() && uses[end].key == uses[begin].key) ++end;
    const std::size_t faces = end - begin;
    const EdgeUse& first = uses[begin];
    if (faces == 1) {
      ++findings.border_edges;
      if (request.border_edges) findings.border_edge_triangles.push_back(mesh.triangle_numbers[first.triangle]);
    } else if (faces == 2) {
      const EdgeUse& second = uses[begin + 1];
      // Consistent neighbours traverse their shared edge in opposite directions (glTF 2.0
      // section 3.7.2.1: front faces are counter-clockwise).
      if (first.forward == second.forward) {
        ++findings.inconsistent_winding_edges;
        if (request.winding) findings.inconsistent_winding_triangles.push_back(mesh.triangle_numbers[second.triangle]);
      }
      if (request.non_manifold_vertices) {
        // Join the corners of both triangles at each endpoint of the edge: corners joined this
        // way form the fans around a vertex.
        auto corner_at = [&](const EdgeUse& use, std::uint32_t welded_vertex) {
          const Triangle& w = welded.welded_triangles[use.triangle];
          const std::uint32_t k = w[0] == welded_vertex ? 0 : (w[1] == welded_vertex ? 1 : 2);
          return use.triangle * 3 + k;
        };
        const std::uint32_t low = static_cast<std::uint32_t>(first.key >> 32),
                            high = static_cast<std::uint32_t>(first.key);
        corners.unite(corner_at(first, low), corner_at(second, low));
        corners.unite(corner_at(first, high), corner_at(second, high));
      }
    } else {
      ++findings.non_manifold_edges;
      if (request.non_manifold_edges)
        findings.non_manifold_edge_triangles.push_back(mesh.triangle_numbers[first.triangle]);
      if (request.non_manifold_vertices) {
        on_non_manifold_edge[first.key >> 32] = true;
        on_non_manifold_edge[static_cast<std::uint32_t>(first.key)] = true;
      }
    }
  }

  if (request.non_manifold_vertices) {
    // A manifold vertex has one fan of triangles around it; two or more fans meeting in one
    // point ("bowtie") make it non-manifold. Vertices on a non-manifold edge are that edge's
    // finding already.
    constexpr std::uint32_t none = ~0u;
    std::vector<std::uint32_t> fan_of_vertex(welded.welded_positions.size(), none);
    std::vector<bool> reported(welded.welded_positions.size(), false);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (!welded.usable(t)) continue;
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t vertex = welded.welded_triangles[t][k];
        const std::uint32_t fan = corners.find(static_cast<std::uint32_t>(t) * 3 + k);
        if (fan_of_vertex[vertex] == none) {
          fan_of_vertex[vertex] = fan;
        } else if (fan_of_vertex[vertex] != fan && !reported[vertex] && !on_non_manifold_edge[vertex]) {
          reported[vertex] = true;
          findings.non_manifold_vertices.push_back(mesh.triangles[t][k]);
        }
      }
    }
    std::sort(findings.non_manifold_vertices.begin(), findings.non_manifold_vertices.end());
  }
  for (auto* list : {&findings.border_edge_triangles, &findings.non_manifold_edge_triangles,
                     &findings.inconsistent_winding_triangles}) {
    std::sort(list->begin(), list->end());
    list->erase(std::unique(list->begin(), list->end()), list->end());
  }
  return findings;
}

}  // namespace gltf_pbr::mesh
