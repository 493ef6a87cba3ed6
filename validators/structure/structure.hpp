// Structure validation: the Khronos glTF-Validator's issue codes (rules/structure.json), computed
// from the raw bytes of a .gltf or .glb, so that documents tinygltf would refuse still get a full
// report.
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>

#include "core/report.hpp"
#include "core/resources.hpp"
#include "rules/rule_set.hpp"

namespace gltf_pbr {

struct StructureOptions {
  bool validate_resources = true;   // read external buffers and images, and check their data
  bool decode_draco = true;         // run the data checks inside KHR_draco_mesh_compression
  bool allow_outside_uris = false;  // core's resolve_uri policy, as for every command
  // The file's resources, when later steps will read them too (validate and convert hand the same
  // ones to the loader); their policy then governs, not allow_outside_uris. The step makes its own
  // when null.
  std::shared_ptr<FileResources> resources;
};

// Fills report.mime_type, report.messages (in the reference validator's order, with its pointers
// or byte offsets and severities) and report.info. `file` resolves relative URIs. Returns whether
// the document has an error-severity issue, counting those the rules leave out of the report.
bool validate_structure(const std::filesystem::path& file, std::span<const std::uint8_t> bytes, const RuleSet& rules,
                        const StructureOptions& options, Report& report);

}  // namespace gltf_pbr
