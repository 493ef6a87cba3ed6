#include "validators/validate.hpp"

#include <optional>
#include <set>

#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "validators/materials/materials.hpp"
#include "validators/mesh/mesh_checks.hpp"
#include "validators/structure/structure.hpp"

namespace gltf_pbr {

namespace {
bool wants(const ValidateOptions& options, ValidationStep step) { return options.steps.contains(step); }

// Prefixed to a loader failure when the structure step ran, so the report says what was skipped.
constexpr const char* kChecksDidNotRun = "the material, texture and mesh checks did not run: ";

Issue load_failure_issue(const InputError& error) {
  // core/load names a place by JSON pointer or, for GLB and JSON syntax errors, by byte offset.
  return Issue{"IO_ERROR", error.reason, Severity::Error, error.pointer, error.offset, 1};
}
}  // namespace

Report validate_file(const std::filesystem::path& file, const std::string& uri, const RuleSet& rules,
                     const IssuePolicy& policy, const ValidateOptions& options) {
  Report report;
  report.uri = uri;
  report.max_listed_per_code = policy.max_listed_per_code;
  const std::optional<MappedFile> mapped = MappedFile::open(file);  // every step reads these bytes
  if (!mapped) {
    report.add({"IO_ERROR", "Cannot read the file.", Severity::Error, "", {}, 1});
    return report;
  }
  ++work_counters().documents_read;
  const std::span<const std::uint8_t> bytes = mapped->bytes();
  // One set of resources for every step: each external file is opened once, each Draco mesh decoded
  // once (held for the mesh step when the structure step decodes it first).
  const bool both_read_meshes = wants(options, ValidationStep::Structure) && wants(options, ValidationStep::Meshes);
  const auto resources =
      std::make_shared<FileResources>(file.parent_path(), options.allow_outside_uris, both_read_meshes);

  bool structure_found_errors = false;
  if (wants(options, ValidationStep::Structure)) {
    StructureOptions structure_options;
    structure_options.resources = resources;
    try {
      structure_found_errors = validate_structure(file, bytes, rules, structure_options, report);
    } catch (const std::bad_alloc&) {
      report.add({"IO_ERROR", "out of memory in the structure checks", Severity::Error, "", std::nullopt, 1});
      structure_found_errors = true;
    } catch (const std::exception& error) {  // ours, not the document's: a report, not a lost batch
      report.add({"IO_ERROR", std::string("the structure checks did not finish: ") + error.what(), Severity::Error, "",
                  std::nullopt, 1});
      structure_found_errors = true;
    }
  } else {
    const bool glb = bytes.size() >= 4 && bytes[0] == 'g' && bytes[1] == 'l' && bytes[2] == 'T' && bytes[3] == 'F';
    report.mime_type = glb ? "model/gltf-binary" : "model/gltf+json";
  }

  const bool needs_document = wants(options, ValidationStep::Materials) || wants(options, ValidationStep::Textures) || wants(options, ValidationStep::Meshes);
  std::optional<Asset> asset;
  if (needs_document) {
    try {
      asset = load_asset(file, LoadOptions{options.allow_outside_uris, resources, bytes});
    } catch (const InputError& error) {
      // The structure step owns saying why a document is unreadable, in the reference's codes (which
      // the config may silence). When it did not run, or found no error at all (the loader refuses
      // more than the spec: a buffer longer than its byteLength), the loader's reason is the
      // error. Either way the steps that needed the document must not vanish silently:
      // PBR_CHECKS_NOT_RUN says so.
      Issue issue = load_failure_issue(error);
      if (!structure_found_errors) {
        if (wants(options, ValidationStep::Structure)) issue.message = kChecksDidNotRun + issue.message;
      } else if (const Rule* rule = rules.find("PBR_CHECKS_NOT_RUN"); rule && rule->enabled) {
        // The error is already in the report, in the reference's codes; say what it cost.
        issue.code = rule->code;
        issue.severity = rule->severity;
        issue.message = rule->format({issue.message});
      } else {
        issue.code.clear();
      }
      if (!issue.code.empty()) report.add(std::move(issue));
    } catch (const std::bad_alloc&) {
      report.add({"IO_ERROR", kChecksDidNotRun + std::string("out of memory loading the document"), Severity::Error, "",
                  std::nullopt, 1});
    } catch (const std::exception& error) {
      // Anything else is our loader's fault, not the document's: say so instead of ending the batch.
      report.add({"IO_ERROR", kChecksDidNotRun + std::string(error.what()), Severity::Error, "", std::nullopt, 1});
    }
  }
  if (asset) {
    for (const auto& material : asset->model.materials) report.material_names.push_back(material.name);
    try {
      if (wants(options, ValidationStep::Materials) || wants(options, ValidationStep::Textures)) {
        MaterialCheckOptions material_options;
        material_options.materials = wants(options, ValidationStep::Materials);
        material_options.textures = wants(options, ValidationStep::Textures);
        material_options.heatmaps_dir = options.heatmaps_dir;
        material_options.npot_dimensions = !wants(options, ValidationStep::Structure);
        validate_materials(*asset, rules, material_options, report);
      }
      if (wants(options, ValidationStep::Meshes))
        validate_meshes(*asset, rules, MeshCheckOptions{options.self_intersections}, report);
    } catch (const std::bad_alloc&) {
      report.add({"IO_ERROR",
                  "out of memory in the material, texture or mesh checks (--max-image-pixels lowers the "
                  "largest image decoded)",
                  Severity::Error, "", std::nullopt, 1});
    } catch (const std::exception& error) {
      // A step that cannot finish (a heat map that cannot be written, memory) still leaves a report
      // that says so, rather than ending the whole batch.
      report.add({"IO_ERROR", error.what(), Severity::Error, "", std::nullopt, 1});
    }
  }
  apply_policy(policy, report);
  return report;
}

std::optional<Issue> first_value_error(const std::filesystem::path& file, std::span<const std::uint8_t> bytes,
                                       const RuleSet& rules, std::shared_ptr<FileResources> resources) {
  // Only the errors whose value tinygltf does not keep as it was: a value of the wrong type is
  // read as absent, a negative offset, length, stride or count (read unsigned) as 0, and JSON or a
  // GLB container that does not parse whole is cut. A value outside its schema range that is kept
  // as written (gold's specular 1.022, a lowercase alphaMode, a dangling index) is not a loss:
  // the conversion handles or keeps it (DESIGN.md: F0 above 1 must convert).
  // INVALID_INDEX is how the structure step names any non-integer (or negative) index, as the
  // reference does: tinygltf reads such an element as absent or as a wrapped integer.
  static const std::set<std::string> kDroppedCodes{"ARRAY_TYPE_MISMATCH", "TYPE_MISMATCH", "INVALID_JSON",
                                                   "UNDEFINED_PROPERTY", "INVALID_INDEX"};
  static const std::set<std::string> kUnsignedProperties{"byteOffset", "byteLength", "byteStride", "count"};
  StructureOptions options;
  options.validate_resources = false;
  options.decode_draco = false;
  options.resources = std::move(resources);
  Report report;
  validate_structure(file, bytes, rules, options, report);
  for (const Issue& issue : report.messages) {
    if (issue.severity != Severity::Error) continue;
    const std::string property = issue.pointer.substr(issue.pointer.rfind('/') + 1);
    // A null (some exporters write one for an absent value) is a type mismatch that drops nothing.
    const bool null_value =
        issue.code == "TYPE_MISMATCH" && issue.message.find(" value null is not ") != std::string::npos;
    if ((kDroppedCodes.contains(issue.code) && !null_value) || issue.code.rfind("GLB_", 0) == 0 ||
        (issue.code == "VALUE_NOT_IN_RANGE" && kUnsignedProperties.contains(property)))
      return issue;
  }
  return std::nullopt;
}

}  // namespace gltf_pbr
