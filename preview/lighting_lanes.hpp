// The lighting pass's per-pixel work eight pixels at a time (lighting_lanes.cpp): light_both runs
// it row by row. The same sums as the scalar reference, light_both_reference (lighting.hpp), lane
// by lane.
#pragma once
#include <cstdint>

#include "preview/lighting.hpp"
#include "preview/raster.hpp"

namespace gltf_pbr::preview {

struct LightingPass {
  const GBuffers& gbuffers;
  const Environment& env;
  const RayGenerator& rays;
  const LightingOptions& options;
  LitPair& out;  // sized for every pixel
  bool keep_radiance;
};

// Lights row y of pass.gbuffers into pass.out.
void light_row(const LightingPass& pass, std::int64_t y);

}  // namespace gltf_pbr::preview
