// Rasterizer properties on scenes built in code: watertight edges, depth order, culling,
// perspective-correct interpolation, and scale-free framing.
#include "preview/raster.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace gltf_pbr::preview {
namespace {

struct SceneBuilder {
  Scene scene;
  SceneBuilder() {
    scene.materials.resize(2);
    scene.materials[1].double_sided = true;
  }
  std::uint32_t vertex(glm::vec3 p, glm::vec2 uv = {}) {
    Vertex v;
    v.position = p;
    v.normal = glm::vec3(0, 0, 1);
    v.uv[0] = uv;
    scene.vertices.push_back(v);
    scene.bounds.add(glm::dvec3(p));
    return static_cast<std::uint32_t>(scene.vertices.size() - 1);
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, int material = 0) {
    scene.triangles.push_back({{a, b, c}, material});
  }
};

Camera looking_down_minus_z(double distance) {
  Camera camera;
  camera.eye = glm::dvec3(0, 0, distance);
  camera.tan_half_fov_y = std::tan(0.5);
  camera.near = distance * 1e-3;
  return camera;
}

TEST(Raster, TriangleFanLeavesNoCracks) {
  // 97 thin triangles around a centre: every pixel well inside the disc must be covered once
  // the fixed-point edges with the top-left rule are watertight.
  SceneBuilder b;
  const std::uint32_t centre = b.vertex({0.013f, -0.007f, 0});
  const int n = 97;
  std::vector<std::uint32_t> rim;
  for (int i = 0; i < n; ++i) {
    const float a = 2.0f * 3.14159265f * static_cast<float>(i) / n;
    rim.push_back(b.vertex({std::cos(a), std::sin(a), 0}));
  }
  for (int i = 0; i < n; ++i) b.triangle(centre, rim[static_cast<size_t>(i)], rim[static_cast<size_t>((i + 1) % n)]);
  const Camera camera = looking_down_minus_z(2.5);
  const VisibilityBuffer vis = rasterize(b.scene, camera, 257, 257);
  int holes = 0, inside = 0;
  for (int y = 0; y < 257; ++y)
    for (int x = 0; x < 257; ++x) {
      const glm::vec3 ray = view_ray(camera, x + 0.5f, y + 0.5f, 257, 257);
      const glm::vec3 hit = glm::vec3(camera.eye) + ray * static_cast<float>(2.5 / -ray.z);
      if (glm::length(glm::vec2(hit)) > 0.97f) continue;
      ++inside;
      holes += vis.samples[static_cast<size_t>(y * 257 + x)].empty();
    }
  EXPECT_GT(inside, 10000);
  EXPECT_EQ(holes, 0);
}

TEST(Raster, NearerSurfaceWinsWhateverTheOrder) {
  for (bool near_first : {true, false}) {
    SceneBuilder b;
    auto quad = [&](float z) {
      const auto a = b.vertex({-1, -1, z}), c = b.vertex({1, -1, z}), d = b.vertex({1, 1, z}), e = b.vertex({-1, 1, z});
      b.triangle(a, c, d);
      b.triangle(a, d, e);
    };
    quad(near_first ? 0.5f : -0.5f);
    quad(near_first ? -0.5f : 0.5f);
    const VisibilityBuffer vis = rasterize(b.scene, looking_down_minus_z(4.0), 64, 64);
    const VisibilitySample& centre = vis.samples[32 * 64 + 32];
    ASSERT_FALSE(centre.empty());
    EXPECT_EQ(centre.index() / 2, near_first ? 0u : 1u);
    EXPECT_NEAR(1.0f / centre.inverse_depth, 3.5f, 1e-3f);
  }
}

TEST(Raster, BackFacesAreCulledUnlessDoubleSided) {
  for (int material : {0, 1}) {
    SceneBuilder b;
    const auto a = b.vertex({-1, -1, 0}), c = b.vertex({1, -1, 0}), d = b.vertex({0, 1, 0});
    b.triangle(a, d, c, material);  // clockwise seen from +Z: a back face
    const VisibilityBuffer vis = rasterize(b.scene, looking_down_minus_z(4.0), 64, 64);
    const VisibilitySample& centre = vis.samples[34 * 64 + 32];
    EXPECT_EQ(centre.empty(), material == 0);
    if (material == 1) {
      EXPECT_TRUE(centre.back_facing());
    }
  }
}

TEST(Raster, TrianglesWithVerticesAtNaNInfinityOrFloatsEdgeAreSkippedOthersDrawn) {
  // A hostile skin or matrix can put vertices at NaN, at infinity or near float's largest value:
  // their triangles are skipped or clipped (never an out-of-range conversion to fixed point, which
  // the sanitizer build reports), and a sound triangle beside them is drawn as ever.
  const float huge = 3.0e38f;
  for (const glm::vec3 bad : {glm::vec3(NAN, 0, 0), glm::vec3(0, INFINITY, 0), glm::vec3(-INFINITY, 0, 0),
                              glm::vec3(huge, -huge, 0), glm::vec3(0, 0, huge), glm::vec3(-huge, huge, -huge)}) {
    SCOPED_TRACE(testing::Message() << bad.x << " " << bad.y << " " << bad.z);
    SceneBuilder b;
    b.triangle(b.vertex(bad), b.vertex({1, -1, 0}), b.vertex({0, 1, 0}), 1);
    b.triangle(b.vertex({-1, -1, 0}), b.vertex({1, -1, 0}), b.vertex({0, 1, 0}));
    b.triangle(b.vertex({0, 0, 0}), b.vertex(bad), b.vertex(-bad), 1);
    RasterStats stats;
    const VisibilityBuffer vis = rasterize(b.scene, looking_down_minus_z(4.0), 64, 64, &stats);
    const VisibilitySample& centre = vis.samples[34 * 64 + 32];
    ASSERT_FALSE(centre.empty());
    const bool finite = std::isfinite(bad.x) && std::isfinite(bad.y) && std::isfinite(bad.z);
    if (!finite) {
      EXPECT_EQ(stats.culled, 2);  // the two with a vertex at NaN or infinity
    }
    for (const VisibilitySample& sample : vis.samples)
      if (!sample.empty()) {
        EXPECT_TRUE(std::isfinite(sample.inverse_depth));
        if (!finite) {
          EXPECT_EQ(sample.index(), 1u);
        }
      }
  }
}

TEST(Raster, BarycentricsArePerspectiveCorrect) {
  // A floor receding from the camera: the interpolated UV at each pixel equals the UV of the ray's
  // exact intersection with the plane (screen-linear interpolation would miss by up to ~25%).
  SceneBuilder b;
  const auto a = b.vertex({-1, -1, 0}, {0, 0}), c = b.vertex({1, -1, 0}, {1, 0}), d = b.vertex({1, 1, -20}, {1, 1}),
             e = b.vertex({-1, 1, -20}, {0, 1});
  b.triangle(a, c, d);
  b.triangle(a, d, e);
  Camera camera = looking_down_minus_z(2.0);
  const VisibilityBuffer vis = rasterize(b.scene, camera, 128, 128);
  int checked = 0;
  for (int y = 0; y < 128; y += 7)
    for (int x = 0; x < 128; x += 7) {
      const VisibilitySample& s = vis.samples[static_cast<size_t>(y * 128 + x)];
      if (s.empty()) continue;
      const SurfacePoint p = interpolate(b.scene, s.index(), glm::vec3(1 - s.b1 - s.b2, s.b1, s.b2));
      // Plane through the quad: y' = (1 + y) / 2 along the slope, z = -20 (1 + y) / 2.
      const glm::dvec3 ray = glm::dvec3(view_ray(camera, x + 0.5f, y + 0.5f, 128, 128));
      // Points P = (px, py, -10 (py + 1)); solve eye + t ray on that plane.
      const double t = (-10.0 - camera.eye.z) / (ray.z + 10.0 * ray.y);
      const glm::dvec3 hit = camera.eye + ray * t;
      EXPECT_NEAR(p.uv[0].y, (hit.y + 1.0) / 2.0, 2e-3) << x << "," << y;
      EXPECT_NEAR(p.uv[0].x, (hit.x + 1.0) / 2.0, 2e-3) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 60);
}

std::vector<bool> coverage_of_box(double size, glm::dvec3 offset) {
  SceneBuilder b;
  const glm::vec3 corners[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  std::uint32_t v[8];
  for (int i = 0; i < 8; ++i) v[i] = b.vertex(glm::vec3(offset + glm::dvec3(corners[i]) * size));
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  for (const auto& f : faces) {
    b.triangle(v[f[0]], v[f[1]], v[f[2]]);
    b.triangle(v[f[0]], v[f[2]], v[f[3]]);
  }
  const Camera camera = frame_camera(b.scene.bounds, 35, 20, 40, 1.0);
  const VisibilityBuffer vis = rasterize(b.scene, camera, 96, 96);
  std::vector<bool> covered;
  for (const auto& s : vis.samples) covered.push_back(!s.empty());
  return covered;
}

TEST(Framing, TinyAndHugeScenesFillTheFrameAlike) {
  // A 0.1 mm box at the origin and a 100 km box 100 km away give the same picture as a 1 m box.
  const auto reference = coverage_of_box(1.0, glm::dvec3(0.0));
  long covered = 0;
  for (bool c : reference) covered += c;
  EXPECT_GT(covered, 96 * 96 / 5);      // the box fills a good part of the frame...
  EXPECT_LT(covered, 96 * 96 * 4 / 5);  // ...without spilling over it
  for (bool c : {reference[0], reference[95], reference[96 * 95], reference[96 * 96 - 1]}) EXPECT_FALSE(c);
  for (auto [size, offset] : {std::pair{1e-4, glm::dvec3(0.0)}, std::pair{1e5, glm::dvec3(1e5, -3e4, 2e5)}}) {
    const auto other = coverage_of_box(size, offset);
    long differing = 0;
    for (size_t i = 0; i < other.size(); ++i) differing += other[i] != reference[i];
    EXPECT_LE(differing, 20) << "size " << size;
  }
}

TEST(Framing, AScaleBelowFloatsNormalRangeDrawsNothingWhereTheFramingStillDraws) {
  // Framed alike, a box of 1e-30 units fills the frame as a 1 m box does. At 1e-43 (float's
  // denormals) 1 / depth overflows: nothing is drawn, and nothing reaches the fixed-point
  // conversion out of range (the sanitizer build reports that).
  const auto reference = coverage_of_box(1.0, glm::dvec3(0.0));
  const auto small = coverage_of_box(1e-30, glm::dvec3(0.0));
  long differing = 0;
  for (size_t i = 0; i < small.size(); ++i) differing += small[i] != reference[i];
  EXPECT_LE(differing, 20);
  const auto denormal = coverage_of_box(1e-43, glm::dvec3(0.0));
  EXPECT_EQ(std::count(denormal.begin(), denormal.end(), true), 0);
}

}  // namespace
}  // namespace gltf_pbr::preview
