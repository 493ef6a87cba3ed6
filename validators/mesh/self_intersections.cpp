// The one CGAL translation unit (~19 s and 740 MB to compile): self-intersections of a triangle
// soup. CGAL 5.5 has PMP::self_intersections only for face graphs, and a Surface_mesh cannot
// hold the non-manifold or inconsistently wound primitives this step exists to find, so this
// follows PMP's own algorithm (Polygon_mesh_processing/self_intersections.h, 5.5) on the soup:
// box_self_intersection_d over triangle bounding boxes, then exact-predicate tests that ignore
// contact through a shared vertex or edge.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <atomic>
#include <mutex>

#include "validators/mesh/triangle_mesh.hpp"

namespace gltf_pbr::mesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
// Boxes identified by address, handled through pointers, as PMP does (ID_EXPLICIT would use a
// process-wide counter, a race when two files are validated on two threads).
using Box =
    CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t, CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;

#ifdef GLTF_PBR_MESH_WITH_TBB
using Concurrency = CGAL::Parallel_tag;
#else
using Concurrency = CGAL::Sequential_tag;
#endif

struct StopSearch {};  // thrown from the callback once max_pairs pairs are found

// PMP's do_faces_intersect (self_intersections.h, CGAL 5.5) for two welded triangles.
bool faces_intersect(const std::vector<Point>& points, const Triangle& h, const Triangle& g) {
  int shared = 0, h_shared = -1, g_shared = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (h[i] == g[j]) {
        ++shared;
        h_shared = i;
        g_shared = j;
      }
  if (shared >= 3) return false;  // the same face twice: MESH_TRIANGLE_DUPLICATE's finding
  if (shared == 2) {
    // A shared edge: they overlap only when coplanar with the two opposite vertices on the same
    // side of the edge.
    int h_other = 0, g_other = 0;
    for (int i = 0; i < 3; ++i) {
      if (h[i] != g[0] && h[i] != g[1] && h[i] != g[2]) h_other = i;
      if (g[i] != h[0] && g[i] != h[1] && g[i] != h[2]) g_other = i;
    }
    const Point& p = points[h[(h_other + 1) % 3]];
    const Point& q = points[h[(h_other + 2) % 3]];
    const Point& r = points[h[h_other]];
    const Point& s = points[g[g_other]];
    return CGAL::coplanar(p, q, r, s) && CGAL::coplanar_orientation(p, q, r, s) == CGAL::POSITIVE;
  }
  const Kernel::Triangle_3 th(points[h[0]], points[h[1]], points[h[2]]);
  const Kernel::Triangle_3 tg(points[g[0]], points[g[1]], points[g[2]]);
  if (shared == 1) {
    // A shared vertex: they intersect elsewhere only if an edge opposite it crosses the other.
    const Kernel::Segment_3 h_opposite(points[h[(h_shared + 1) % 3]], points[h[(h_shared + 2) % 3]]);
    const Kernel::Segment_3 g_opposite(points[g[(g_shared + 1) % 3]], points[g[(g_shared + 2) % 3]]);
    return CGAL::do_intersect(th, g_opposite) || CGAL::do_intersect(tg, h_opposite);
  }
  return CGAL::do_intersect(th, tg);
}

}  // namespace

SelfIntersections find_self_intersections(const TriangleMesh& mesh, const WeldedMesh& welded, std::size_t max_pairs) {
  SelfIntersections result;
  if (max_pairs == 0) return result;
  std::vector<Point> points;
  points.reserve(welded.welded_positions.size());
  for (const glm::dvec3& p : welded.welded_positions) points.emplace_back(p.x, p.y, p.z);

  std::vector<Box> boxes;
  boxes.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!welded.usable(t)) continue;  // degenerate faces have no plane; PMP leaves them out too
    const Triangle& w = welded.welded_triangles[t];
    boxes.emplace_back(points[w[0]].bbox() + points[w[1]].bbox() + points[w[2]].bbox(), t);
  }
  std::vector<const Box*> box_pointers;
  box_pointers.reserve(boxes.size());
  for (const Box& box : boxes) box_pointers.push_back(&box);

  std::mutex found_mutex;
  std::atomic<bool> full{false};
  auto report_pair = [&](const Box* a, const Box* b) {
    if (full.load(std::memory_order_relaxed)) return;
    const std::size_t ta = a->info(), tb = b->info();
    if (!faces_intersect(points, welded.welded_triangles[ta], welded.welded_triangles[tb])) return;
    const std::lock_guard lock(found_mutex);
    if (result.pairs.size() >= max_pairs) return;
    result.pairs.emplace_back(std::min(mesh.triangle_numbers[ta], mesh.triangle_numbers[tb]),
                              std::max(mesh.triangle_numbers[ta], mesh.triangle_numbers[tb]));
    if (result.pairs.size() >= max_pairs) {
      full = true;
      throw StopSearch{};
    }
  };
  try {
    // Cutoff 2000 boxes per leaf as PMP uses it.
    CGAL::box_self_intersection_d<Concurrency>(box_pointers.begin(), box_pointers.end(), report_pair,
                                               std::ptrdiff_t{2000});
  } catch (const StopSearch&) {
    result.stopped_at_limit = true;
  }
  std::sort(result.pairs.begin(), result.pairs.end());
  return result;
}

}  // namespace gltf_pbr::mesh
