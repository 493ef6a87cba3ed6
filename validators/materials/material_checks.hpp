// Internals shared by the material (PBR_*) and texture (IMAGE_*) checks of one file.
#pragma once
#include <set>
#include <string>
#include <vector>

#include "core/asset.hpp"
#include "core/material_model.hpp"
#include "core/report.hpp"
#include "rules/rule_set.hpp"
#include "validators/materials/materials.hpp"

namespace gltf_pbr {

// Adds an issue for `code` through the one sink (rules/issue_sink.hpp): text arguments, never quoted.
void add_issue(const RuleSet& rules, const std::string& code, const std::vector<std::string>& arguments,
               const std::string& pointer, Report& report);

// The file's images, each decoded at most once for both kinds of check. A failed decode is
// reported once (IMAGE_UNDECODABLE, when enabled) and then reads as nullptr.
class TexelSource {
 public:
  // `shared`: a run's decoded pixels to read and add to; null: its own.
  TexelSource(const Asset& asset, DecodedImages* shared) : asset_(asset), decoded_(shared ? *shared : own_) {}
  const Pixels* get(int image, const RuleSet& rules, Report& report);

 private:
  const Asset& asset_;
  DecodedImages own_;
  DecodedImages& decoded_;
  std::set<int> failed_;
};

// PBR_* checks of every material (validators/materials/materials.cpp).
void check_material_plausibility(const Asset& asset, const RuleSet& rules, const MaterialCheckOptions& options,
                                 TexelSource& images, Report& report);

// IMAGE_* checks of every image that materials use (validators/materials/texture_checks.cpp).
void check_material_textures(const Asset& asset, const RuleSet& rules, const MaterialCheckOptions& options,
                             TexelSource& images, Report& report);

}  // namespace gltf_pbr
