// `gltf-pbr validate`: runs the chosen steps over one file into one Khronos-schema report.
//   structure  the Khronos validator's codes, on the raw bytes (validators/structure/)
//   materials  PBR_* plausibility of every material, factors and texels (validators/materials/)
//   textures   IMAGE_* checks of normal maps, constant images, channel use, sizes (validators/materials/)
//   meshes     MESH_* geometry checks with CGAL, Draco included (validators/mesh/)
// Each step does only the work its enabled rules need: images are decoded only for texel rules,
// Draco meshes only for data and mesh checks.
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>

#include "core/report.hpp"
#include "gltf_pbr/gltf_pbr.hpp"  // ValidationStep
#include "rules/rule_set.hpp"

namespace gltf_pbr {

class FileResources;

inline const std::set<ValidationStep>& all_validation_steps() {
  static const std::set<ValidationStep> steps{ValidationStep::Structure, ValidationStep::Materials,
                                              ValidationStep::Textures, ValidationStep::Meshes};
  return steps;
}

struct ValidateOptions {
  std::set<ValidationStep> steps = all_validation_steps();
  std::filesystem::path heatmaps_dir;  // empty: no heat-map images
  bool allow_outside_uris = false;
  bool self_intersections = true;      // the costliest mesh check
};

// Validates `file`; `uri` is how the report names it (the path as the user gave it). Never throws
// for bad input: problems become issues in the report.
Report validate_file(const std::filesystem::path& file, const std::string& uri, const RuleSet& rules,
                     const IssuePolicy& policy, const ValidateOptions& options);

// For commands that rewrite a file (convert): the first error the structure step finds, without
// reading resources, in a value that loading would drop or misread: a wrong type (`children:
// [1.5]`, an extension that is an array), a negative offset, length, stride or count, a missing
// required property, JSON that does not end where it should, a broken GLB container. Writing on
// from such a document would silently hold less than the input. Values kept as written (out of
// range but read, such as gold's specular 1.022) are not refused.
// std::nullopt when there is none. `bytes` are the file's; the structure step keeps its JSON tree
// in `resources`, so the loader handed the same resources and bytes parses nothing again.
std::optional<Issue> first_value_error(const std::filesystem::path& file, std::span<const std::uint8_t> bytes,
                                       const RuleSet& rules, std::shared_ptr<FileResources> resources);

}  // namespace gltf_pbr
