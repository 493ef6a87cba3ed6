// Material plausibility (PBR_* codes) and texture checks (IMAGE_* codes), thresholds from
// rules/materials.json.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "core/asset.hpp"
#include "core/image.hpp"
#include "core/report.hpp"
#include "rules/rule_set.hpp"

namespace gltf_pbr {

struct MaterialCheckOptions {
  bool materials = true;  // PBR_* rules, factors and texels
  bool textures = true;   // IMAGE_* rules
  // IMAGE_NPOT_DIMENSIONS, the structure step's code, for a run without that step (validate.cpp).
  bool npot_dimensions = true;
  // Empty: no heat maps. Else, for every textured material with a reported PBR_* texel rule, one
  // 8-bit RGB PNG "<file stem>-material<M>-texture<T>.png" on the bake's grid (core/image.hpp
  // bake_grid: the larger width and height of the textures the checks read; T is the largest of
  // them, whose size it is unless another is wider or taller):
  //   blue   (0, 0, 255)     too dark: dielectric F0 too low, metal F0 too dark, albedo too dark
  //   red    (255, 0, 0)     too bright: dielectric F0 too high, albedo too bright, energy > 1
  //   yellow (255, 255, 0)   out of range: chromatic dielectric specular, metal with diffuse,
  //                          partial metalness, roughness 0
  //   grey   (v, v, v), v <= 127: passing texel, the albedo's sRGB luminance halved
  // Only the reported rules are painted; where several fail, out of range wins over too bright
  // over too dark. PBR_F0_ABOVE_ONE (gold is real) is never painted.
  std::filesystem::path heatmaps_dir;
  // Pixels another step of the run already decoded (a preview's conversion), read and added to
  // instead of decoding again; null: the checks keep their own.
  DecodedImages* decoded = nullptr;
};

// The heat map's file name for material `material` and texture `texture` of the asset whose file
// stem is `stem`; and the stem of the asset whose heat map `name` would be, if it is one (so a run
// can refuse to write one over a file it reads before it starts).
std::string heat_map_name(const std::string& stem, int material, int texture);
std::optional<std::string> heat_map_stem(std::string_view name);

// Every material is evaluated under its own model (core/material_model.hpp). An image is decoded
// only when an enabled texel rule reads it, and at most once per call.
void validate_materials(const Asset& asset, const RuleSet& rules, const MaterialCheckOptions& options, Report& report);

}  // namespace gltf_pbr
