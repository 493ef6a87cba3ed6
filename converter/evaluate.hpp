// How far a converted asset (ours or anyone's) is from its legacy spec-gloss original, as a viewer
// would see it: the error model of solver.hpp evaluated on a UV grid of each material.
#pragma once
#include <string>
#include <vector>

#include "converter/error_stats.hpp"
#include "core/asset.hpp"

namespace gltf_pbr {

enum class Viewer {
  CoreOnly,  // baseColor, metallic and roughness only (KHR_materials_specular / _ior ignored)
  Full,      // also KHR_materials_specular and KHR_materials_ior
};

struct MaterialComparison {
  int index = -1;
  std::string name;
  size_t samples = 0;
  ReflectanceError error;  // converted against legacy reading A
};

// Compares every material of `legacy` that has spec-gloss with the material of the same index in
// `converted`, on the texels a bake reads: the textures of both on their common bake grid
// (core/image.hpp's bake_grid and resize, as convert and the material checks read them; both sides
// must use the same texture coordinates, as conversions do), sampled every stride-th texel as the
// bake samples its error (the stride is texels / max_error_samples rounded down, so up to twice
// that many samples; 0: every texel). Factor-only pairs take one sample. So compare of convert's
// own output gives the figures of convert's report.
std::vector<MaterialComparison> compare_conversion(const Asset& legacy, const Asset& converted, Viewer viewer,
                                                   size_t max_error_samples = size_t{1} << 16);

}  // namespace gltf_pbr
