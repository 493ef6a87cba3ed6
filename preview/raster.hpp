// Our rasterizer: tiled, multi-threaded, watertight (fixed-point edge functions with the top-left
// rule), perspective-correct, depth-tested on 1/w. It writes a visibility buffer (triangle id +
// barycentrics per pixel); the G-buffer passes resolve materials from it, once for each side.
#pragma once
#include <atomic>
#include <cstdint>
#include <glm/vec3.hpp>
#include <thread>
#include <vector>

#include "core/parallel.hpp"  // parallel_dynamic, which the passes use
#include "preview/scene.hpp"
#include "core/texel_buffer.hpp"

namespace gltf_pbr::preview {

// A pinhole camera in world space (double precision: a scene 1e5 m away from its origin keeps
// its sub-millimetre detail once vertices are made camera-relative).
struct Camera {
  glm::dvec3 eye{0.0}, forward{0, 0, -1}, right{1, 0, 0}, up{0, 1, 0};  // orthonormal
  double tan_half_fov_y = 0.36, aspect = 1.0;                           // width / height
  double near = 0.01;
  bool orthographic = false;     // --grid: rays parallel to `forward`
  double ortho_half_height = 1;  // world units
};

// Looks at the bounding sphere of `bounds` from spherical angles (degrees; yaw about +Y from +Z,
// pitch above the horizon) at the distance where the sphere fills the narrower field of view.
// Scale-free: a scene 1e-4 m or 1e5 m across gives the same picture.
Camera frame_camera(const Bounds& bounds, double yaw_degrees, double pitch_degrees, double fov_y_degrees,
                    double aspect);
// A glTF camera (glTF 2.0 section 3.10.2: looks down its node's -Z, +Y up); the image aspect wins.
Camera camera_from_gltf(const SceneCamera& camera, double aspect);

// World-space direction of the ray through pixel coordinates (x, y) (pixel centres at +0.5).
glm::vec3 view_ray(const Camera& camera, float x, float y, int width, int height);

// The same rays in float, unnormalised (forward + right sx + up sy), for per-pixel passes.
struct RayGenerator {
  glm::vec3 forward, right_per_pixel, up_per_pixel, corner;  // corner: direction at pixel (0, 0)
  bool orthographic = false;
  RayGenerator(const Camera& camera, int width, int height);
  glm::vec3 unnormalised(float x, float y) const {
    return orthographic ? forward : corner + right_per_pixel * x + up_per_pixel * y;
  }
};

struct VisibilitySample {
  std::uint32_t triangle = 0;  // triangle index + 1; 0 where nothing was drawn
  float b1 = 0, b2 = 0;        // perspective-correct barycentrics of vertices 1 and 2
  float inverse_depth = 0;     // 1 / view depth; larger is nearer
  bool back_facing() const { return (triangle & kBackFacingBit) != 0; }
  std::uint32_t index() const { return (triangle & ~kBackFacingBit) - 1; }
  bool empty() const { return triangle == 0; }
  static constexpr std::uint32_t kBackFacingBit = 1u << 31;
};
static_assert(sizeof(VisibilitySample) == 16);

struct VisibilityBuffer {
  int width = 0, height = 0;
  TexelBuffer<VisibilitySample> samples;  // not zeroed, pages kept for reuse (texel_buffer.hpp)
};

struct RasterStats {
  long long triangles = 0, culled = 0, clipped = 0, drawn_pieces = 0;
};

VisibilityBuffer rasterize(const Scene& scene, const Camera& camera, int width, int height,
                           RasterStats* stats = nullptr);

}  // namespace gltf_pbr::preview
