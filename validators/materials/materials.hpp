// Material plausibility (PBR_* codes) and texture checks (IMAGE_* codes), thresholds from
// rules/materials.json.
#pragma once
#include <filesystem>

#include "core/asset.hpp"
#include "core/report.hpp"
#include "rules/rule_set.hpp"

namespace gltf_pbr {

struct MaterialCheckOptions {
  bool materials = true;               // PBR_* rules, factors and texels
  bool textures = true;                // IMAGE_* rules
  std::filesystem::path heatmaps_dir;  // empty: no heat maps
};

void validate_materials(const Asset& asset, const RuleSet& rules, const MaterialCheckOptions& options, Report& report);

}  // namespace gltf_pbr
