// Tiled rasterization into a visibility buffer (see raster.hpp).
#include "preview/raster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace gltf_pbr::preview {
namespace {

constexpr int kTileSize = 32;
constexpr int kSubpixelBits = 8;  // 1/256 pixel: vertex snapping as in GPUs (D3D11 uses 8 bits)
constexpr double kSubpixel = 1 << kSubpixelBits;

// Round half away from zero, as std::llround, without its libm call (six per triangle: a tenth
// of the setup of a 100k-triangle mesh). Inputs are guard-band bounded, far inside int64.
inline std::int64_t round_to_subpixel(double v) { return static_cast<std::int64_t>(v + (v >= 0.0 ? 0.5 : -0.5)); }
constexpr float kGuardBand = 4.0f;  // clip x, y to +-4 w: screen coordinates stay inside int64 edge range

struct ClipVertex {
  float x, y, w;          // clip space: x, y in [-w, w] on screen, w = view depth
  glm::vec3 barycentric;  // with respect to the original triangle
};

// Sutherland-Hodgman against one plane, `distance` >= 0 inside, into at most kMaxClipVertices.
// Distances and intersections in double: finite float coordinates near float's range would
// overflow in their differences (a NaN that breaks the polygon's convexity). Each plane adds at
// most one vertex to a convex polygon (3 + 5 planes = 8); a polygon that would outgrow the array
// anyway is dropped (count 0), never written past it.
constexpr int kMaxClipVertices = 12;
template <typename Distance>
int clip_polygon(const ClipVertex* in, int count, ClipVertex* out, const Distance& distance) {
  int n = 0;
  for (int i = 0; i < count; ++i) {
    const ClipVertex& a = in[i];
    const ClipVertex& b = in[(i + 1) % count];
    const double da = distance(a), db = distance(b);
    if (n + 2 > kMaxClipVertices) return 0;
    if (da >= 0) out[n++] = a;
    if ((da >= 0) != (db >= 0)) {
      const double t = da / (da - db);
      const auto between = [t](float from, float to) {
        return static_cast<float>(from + (static_cast<double>(to) - from) * t);
      };
      out[n++] = {between(a.x, b.x), between(a.y, b.y), between(a.w, b.w),
                  a.barycentric + (b.barycentric - a.barycentric) * static_cast<float>(t)};
    }
  }
  return n;
}

// A screen-space piece of a triangle (the triangle itself unless clipping cut it), ready to scan.
struct Piece {
  std::int64_t x[3], y[3];  // fixed point, 8 fractional bits
  float inverse_w[3];
  glm::vec3 barycentric_over_w[3];
  int min_x, min_y, max_x, max_y;  // pixel bounds, inclusive
  std::uint32_t triangle;          // index + 1, with the back-facing bit
};

struct EdgeSetup {
  std::int64_t a, b, c;  // E(p) = a px + b py + c, in fixed point
  std::int64_t bias;     // 0 on top-left edges, 1 elsewhere (pixels on the edge belong to one side only)
};

EdgeSetup edge(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by) {
  EdgeSetup e{ay - by, bx - ax, ax * by - ay * bx, 0};
  // Top-left rule: include E == 0 only for edges with a > 0, or a == 0 and b > 0. The opposite
  // triangle sees the shared edge negated, so exactly one of the two owns those pixels.
  e.bias = (e.a > 0 || (e.a == 0 && e.b > 0)) ? 0 : 1;
  return e;
}

// 4x4 Bayer matrix: alphaMode BLEND is drawn as ordered screen-door transparency, which a deferred
// G-buffer can hold (one surface per pixel); the threshold pattern averages to the right coverage.
constexpr float kBayer4[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};

}  // namespace

Camera frame_camera(const Bounds& bounds, double yaw_degrees, double pitch_degrees, double fov_y_degrees,
                    double aspect) {
  Camera camera;
  camera.aspect = aspect;
  camera.tan_half_fov_y = std::tan(glm::radians(fov_y_degrees) * 0.5);
  glm::dvec3 center(0.0);
  double radius = 1.0;
  if (!bounds.empty()) {
    center = (bounds.min + bounds.max) * 0.5;
    radius = glm::length(bounds.max - bounds.min) * 0.5;
    if (!(radius > 0.0)) radius = std::max(1e-9, std::abs(center.x) * 1e-6 + 1e-9);
  }
  const double yaw = glm::radians(yaw_degrees), pitch = glm::radians(pitch_degrees);
  const glm::dvec3 to_eye(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
  // The sphere fits the narrower half-angle: sin(half angle) = radius / distance.
  const double tan_half = std::min(camera.tan_half_fov_y, camera.tan_half_fov_y * aspect);
  const double half_angle = std::atan(tan_half);
  const double distance = radius / std::sin(half_angle) * 1.02;
  camera.eye = center + to_eye * distance;
  camera.forward = -to_eye;
  const glm::dvec3 world_up = std::abs(to_eye.y) > 0.999 ? glm::dvec3(0, 0, -1) : glm::dvec3(0, 1, 0);
  camera.right = glm::normalize(glm::cross(camera.forward, world_up));
  camera.up = glm::cross(camera.right, camera.forward);
  camera.near = std::max((distance - radius) * 0.5, distance * 1e-6);
  camera.ortho_half_height = radius;
  return camera;
}

Camera camera_from_gltf(const SceneCamera& scene_camera, double aspect) {
  Camera camera;
  const glm::dmat4& m = scene_camera.camera_to_world;
  camera.eye = glm::dvec3(m[3]);
  camera.forward = glm::normalize(-glm::dvec3(m[2]));
  camera.right = glm::normalize(glm::dvec3(m[0]));
  camera.up = glm::normalize(glm::cross(camera.right, camera.forward));
  camera.right = glm::cross(camera.forward, camera.up);
  camera.tan_half_fov_y = std::tan(static_cast<double>(scene_camera.yfov) * 0.5);
  camera.aspect = aspect;
  camera.near = scene_camera.znear > 0 ? scene_camera.znear : 1e-3;
  return camera;
}

glm::vec3 view_ray(const Camera& camera, float x, float y, int width, int height) {
  if (camera.orthographic) return glm::vec3(camera.forward);
  const double sx = (2.0 * x / width - 1.0) * camera.tan_half_fov_y * camera.aspect;
  const double sy = (1.0 - 2.0 * y / height) * camera.tan_half_fov_y;
  return glm::vec3(glm::normalize(camera.forward + camera.right * sx + camera.up * sy));
}

RayGenerator::RayGenerator(const Camera& camera, int width, int height) : orthographic(camera.orthographic) {
  const double sx = 2.0 * camera.tan_half_fov_y * camera.aspect / width, sy = 2.0 * camera.tan_half_fov_y / height;
  forward = glm::vec3(camera.forward);
  right_per_pixel = glm::vec3(camera.right * sx);
  up_per_pixel = glm::vec3(-camera.up * sy);
  corner = glm::vec3(camera.forward - camera.right * (camera.tan_half_fov_y * camera.aspect) +
                     camera.up * camera.tan_half_fov_y);
}

VisibilityBuffer rasterize(const Scene& scene, const Camera& camera, int width, int height, RasterStats* stats) {
  VisibilityBuffer out;
  out.width = width;
  out.height = height;
  out.samples.assign(static_cast<size_t>(width) * static_cast<size_t>(height), VisibilitySample{});
  if (scene.triangles.empty() || width <= 0 || height <= 0) return out;

  // 1. Vertices to clip space, camera-relative in double precision.
  const double scale_x = 1.0 / (camera.tan_half_fov_y * camera.aspect), scale_y = 1.0 / camera.tan_half_fov_y;
  std::vector<glm::vec3> clip(scene.vertices.size());
  parallel_dynamic(static_cast<std::int64_t>((clip.size() + 4095) / 4096), [&](std::int64_t block) {
    const size_t end = std::min(clip.size(), static_cast<size_t>(block + 1) * 4096);
    for (size_t i = static_cast<size_t>(block) * 4096; i < end; ++i) {
      const glm::dvec3 relative = glm::dvec3(scene.vertices[i].position) - camera.eye;
      clip[i] = glm::vec3(glm::dot(relative, camera.right) * scale_x, glm::dot(relative, camera.up) * scale_y,
                          glm::dot(relative, camera.forward));
    }
  });

  // 2. Triangle setup and binning, in chunks whose bins are concatenated in order (submission
  // order decides ties, as on GPUs).
  const int tiles_x = (width + kTileSize - 1) / kTileSize, tiles_y = (height + kTileSize - 1) / kTileSize;
  const std::int64_t chunk_count =
      std::max<std::int64_t>(1, std::min<std::int64_t>(64, static_cast<std::int64_t>(scene.triangles.size() / 2048)));
  struct Chunk {
    std::vector<Piece> pieces;
    std::vector<std::vector<std::uint32_t>> bins;
    RasterStats stats;
  };
  std::vector<Chunk> chunks(static_cast<size_t>(chunk_count));
  const float near = static_cast<float>(camera.near);
  parallel_dynamic(chunk_count, [&](std::int64_t c) {
    Chunk& chunk = chunks[static_cast<size_t>(c)];
    chunk.bins.resize(static_cast<size_t>(tiles_x * tiles_y));
    const size_t begin = scene.triangles.size() * static_cast<size_t>(c) / static_cast<size_t>(chunk_count);
    const size_t end = scene.triangles.size() * static_cast<size_t>(c + 1) / static_cast<size_t>(chunk_count);
    for (size_t t = begin; t < end; ++t) {
      const Triangle& triangle = scene.triangles[t];
      ++chunk.stats.triangles;
      std::array<ClipVertex, kMaxClipVertices> polygon, scratch;
      bool finite = true;
      for (int k = 0; k < 3; ++k) {
        const glm::vec3& v = clip[triangle.vertex[k]];
        finite = finite && std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
        polygon[static_cast<size_t>(k)] = {v.x, v.y, v.z, glm::vec3(k == 0, k == 1, k == 2)};
      }
      // A vertex at NaN or infinity (a hostile skin's weights, a matrix beyond float's range) has no
      // place on screen: its triangle is not drawn.
      if (!finite) {
        ++chunk.stats.culled;
        continue;
      }
      // Trivial rejection: all three outside one plane.
      auto all_outside = [&](auto distance) {
        return distance(polygon[0]) < 0 && distance(polygon[1]) < 0 && distance(polygon[2]) < 0;
      };
      if (all_outside([&](const ClipVertex& v) { return v.w - near; }) ||
          all_outside([](const ClipVertex& v) { return v.w - v.x; }) ||
          all_outside([](const ClipVertex& v) { return v.w + v.x; }) ||
          all_outside([](const ClipVertex& v) { return v.w - v.y; }) ||
          all_outside([](const ClipVertex& v) { return v.w + v.y; })) {
        ++chunk.stats.culled;
        continue;
      }
      int count = 3;
      const auto inside_guard = [&](const ClipVertex& v) {
        return v.w >= near && std::abs(v.x) <= kGuardBand * v.w && std::abs(v.y) <= kGuardBand * v.w;
      };
      if (!inside_guard(polygon[0]) || !inside_guard(polygon[1]) || !inside_guard(polygon[2])) {
        ++chunk.stats.clipped;
        constexpr double guard = kGuardBand;
        count = clip_polygon(polygon.data(), count, scratch.data(),
                             [&](const ClipVertex& v) { return double{v.w} - near; });
        count =
            clip_polygon(scratch.data(), count, polygon.data(), [](const ClipVertex& v) { return guard * v.w - v.x; });
        count =
            clip_polygon(polygon.data(), count, scratch.data(), [](const ClipVertex& v) { return guard * v.w + v.x; });
        count =
            clip_polygon(scratch.data(), count, polygon.data(), [](const ClipVertex& v) { return guard * v.w - v.y; });
        count =
            clip_polygon(polygon.data(), count, scratch.data(), [](const ClipVertex& v) { return guard * v.w + v.y; });
        std::copy_n(scratch.begin(), count, polygon.begin());
        if (count < 3) continue;
      }
      const bool double_sided = scene.materials[static_cast<size_t>(triangle.material)].double_sided;
      // Fan-triangulate the (convex) clipped polygon.
      for (int k = 1; k + 1 < count; ++k) {
        const ClipVertex* corners[3] = {&polygon[0], &polygon[static_cast<size_t>(k)],
                                        &polygon[static_cast<size_t>(k + 1)]};
        Piece piece;
        bool on_screen = true;
        for (int j = 0; j < 3 && on_screen; ++j) {
          const ClipVertex& v = *corners[j];
          const float inv_w = 1.0f / v.w;
          const double sx = (v.x * inv_w * 0.5 + 0.5) * width, sy = (0.5 - v.y * inv_w * 0.5) * height;
          // A depth below float's normal range (a scene of 1e-43 units) has no finite 1 / w: such
          // a piece cannot be placed or interpolated, and is not drawn.
          on_screen = std::isfinite(inv_w) && std::isfinite(sx) && std::isfinite(sy);
          piece.x[j] = on_screen ? round_to_subpixel(sx * kSubpixel) : 0;
          piece.y[j] = on_screen ? round_to_subpixel(sy * kSubpixel) : 0;
          piece.inverse_w[j] = inv_w;
          piece.barycentric_over_w[j] = v.barycentric * inv_w;
        }
        if (!on_screen) {
          ++chunk.stats.culled;
          continue;
        }
        // Signed area in y-down screen space: negative for glTF's counter-clockwise front faces.
        const std::int64_t area = (piece.x[1] - piece.x[0]) * (piece.y[2] - piece.y[0]) -
                                  (piece.x[2] - piece.x[0]) * (piece.y[1] - piece.y[0]);
        if (area == 0) continue;
        const bool back_facing = area > 0;
        if (back_facing && !double_sided) {
          ++chunk.stats.culled;
          continue;
        }
        if (area < 0) {  // scan with a positive orientation
          std::swap(piece.x[1], piece.x[2]);
          std::swap(piece.y[1], piece.y[2]);
          std::swap(piece.inverse_w[1], piece.inverse_w[2]);
          std::swap(piece.barycentric_over_w[1], piece.barycentric_over_w[2]);
        }
        auto pixel_floor = [](std::int64_t v) { return static_cast<int>(v >> kSubpixelBits); };
        piece.min_x = std::max(0, pixel_floor(std::min({piece.x[0], piece.x[1], piece.x[2]})));
        piece.max_x = std::min(width - 1, pixel_floor(std::max({piece.x[0], piece.x[1], piece.x[2]})));
        piece.min_y = std::max(0, pixel_floor(std::min({piece.y[0], piece.y[1], piece.y[2]})));
        piece.max_y = std::min(height - 1, pixel_floor(std::max({piece.y[0], piece.y[1], piece.y[2]})));
        if (piece.min_x > piece.max_x || piece.min_y > piece.max_y) continue;
        piece.triangle = static_cast<std::uint32_t>(t + 1) | (back_facing ? VisibilitySample::kBackFacingBit : 0u);
        const auto index = static_cast<std::uint32_t>(chunk.pieces.size());
        chunk.pieces.push_back(piece);
        ++chunk.stats.drawn_pieces;
        for (int ty = piece.min_y / kTileSize; ty <= piece.max_y / kTileSize; ++ty)
          for (int tx = piece.min_x / kTileSize; tx <= piece.max_x / kTileSize; ++tx)
            chunk.bins[static_cast<size_t>(ty * tiles_x + tx)].push_back(index);
      }
    }
  });

  // 3. Tiles in parallel: scan each binned piece inside the tile, depth test on 1/w.
  parallel_dynamic(static_cast<std::int64_t>(tiles_x) * tiles_y, [&](std::int64_t tile) {
    const int tx = static_cast<int>(tile % tiles_x), ty = static_cast<int>(tile / tiles_x);
    const int x0 = tx * kTileSize, y0 = ty * kTileSize;
    const int x1 = std::min(width, x0 + kTileSize) - 1, y1 = std::min(height, y0 + kTileSize) - 1;
    for (const Chunk& chunk : chunks)
      for (std::uint32_t index : chunk.bins[static_cast<size_t>(tile)]) {
        const Piece& p = chunk.pieces[index];
        const EdgeSetup e0 = edge(p.x[1], p.y[1], p.x[2], p.y[2]);
        const EdgeSetup e1 = edge(p.x[2], p.y[2], p.x[0], p.y[0]);
        const EdgeSetup e2 = edge(p.x[0], p.y[0], p.x[1], p.y[1]);
        const double inverse_area = 1.0 / static_cast<double>(e2.a * p.x[2] + e2.b * p.y[2] + e2.c);
        const int sx0 = std::max(x0, p.min_x), sx1 = std::min(x1, p.max_x);
        const int sy0 = std::max(y0, p.min_y), sy1 = std::min(y1, p.max_y);
        if (sx0 > sx1 || sy0 > sy1) continue;
        const Triangle& triangle = scene.triangles[(p.triangle & ~VisibilitySample::kBackFacingBit) - 1];
        const PreviewMaterial& material = scene.materials[static_cast<size_t>(triangle.material)];
        const bool alpha_tested = material.alpha_mode != AlphaMode::Opaque;
        const std::int64_t step = 1 << kSubpixelBits;
        const std::int64_t px0 = static_cast<std::int64_t>(sx0) * step + step / 2;
        for (int y = sy0; y <= sy1; ++y) {
          const std::int64_t py = static_cast<std::int64_t>(y) * step + step / 2;
          std::int64_t w0 = e0.a * px0 + e0.b * py + e0.c;
          std::int64_t w1 = e1.a * px0 + e1.b * py + e1.c;
          std::int64_t w2 = e2.a * px0 + e2.b * py + e2.c;
          VisibilitySample* row = out.samples.data() + static_cast<size_t>(y) * static_cast<size_t>(width);
          for (int x = sx0; x <= sx1; ++x, w0 += e0.a * step, w1 += e1.a * step, w2 += e2.a * step) {
            if (w0 - e0.bias < 0 || w1 - e1.bias < 0 || w2 - e2.bias < 0) continue;
            const float l0 = static_cast<float>(w0 * inverse_area), l1 = static_cast<float>(w1 * inverse_area);
            const float l2 = 1.0f - l0 - l1;
            const float inverse_depth = l0 * p.inverse_w[0] + l1 * p.inverse_w[1] + l2 * p.inverse_w[2];
            VisibilitySample& sample = row[x];
            if (!(inverse_depth > sample.inverse_depth)) continue;
            const glm::vec3 barycentric =
                (p.barycentric_over_w[0] * l0 + p.barycentric_over_w[1] * l1 + p.barycentric_over_w[2] * l2) /
                inverse_depth;
            if (alpha_tested) {
              const SurfacePoint point =
                  interpolate(scene, (p.triangle & ~VisibilitySample::kBackFacingBit) - 1, barycentric);
              const float alpha = surface_alpha(scene, material, point);
              const float threshold = material.alpha_mode == AlphaMode::Mask
                                          ? material.alpha_cutoff
                                          : (kBayer4[(y & 3) * 4 + (x & 3)] + 0.5f) / 16.0f;
              if (!(alpha >= threshold)) continue;
            }
            sample.triangle = p.triangle;
            sample.b1 = barycentric.y;
            sample.b2 = barycentric.z;
            sample.inverse_depth = inverse_depth;
          }
        }
      }
  });
  if (stats) {
    *stats = {};
    for (const Chunk& chunk : chunks) {
      stats->triangles += chunk.stats.triangles;
      stats->culled += chunk.stats.culled;
      stats->clipped += chunk.stats.clipped;
      stats->drawn_pieces += chunk.stats.drawn_pieces;
    }
  }
  return out;
}

}  // namespace gltf_pbr::preview
