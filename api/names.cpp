// The names of the public enumerations, as the tool's options, its reports and the Python module
// spell them, and the library's version.
#include "api/files.hpp"
#include "core/enum_names.hpp"
#include "core/version.hpp"
#include "gltf_pbr/gltf_pbr.hpp"
#include "rules/rule_set.hpp"

namespace gltf_pbr {
namespace {

constexpr NameTable<Target, 2> kTargets{{{Target::Metalness, "metalness"}, {Target::Specular, "specular"}}};
constexpr NameTable<SolverEffort, 4> kEfforts{{{SolverEffort::Fast, "fast"},
                                               {SolverEffort::Balanced, "balanced"},
                                               {SolverEffort::Exact, "exact"},
                                               {SolverEffort::Reference, "reference"}}};
constexpr NameTable<ErrorModel, 2> kErrorModels{
    {{ErrorModel::NormalIncidence, "normal-incidence"}, {ErrorModel::Appearance, "appearance"}}};
constexpr NameTable<FileStatus, 3> kStatuses{
    {{FileStatus::Converted, "converted"}, {FileStatus::Copied, "copied"}, {FileStatus::Failed, "failed"}}};
constexpr NameTable<ValidationStep, 4> kSteps{{{ValidationStep::Structure, "structure"},
                                               {ValidationStep::Materials, "materials"},
                                               {ValidationStep::Textures, "textures"},
                                               {ValidationStep::Meshes, "meshes"}}};

}  // namespace

std::string version() { return tool_version(); }

std::optional<Target> target_from_name(std::string_view name) { return from_name(kTargets, name); }
std::optional<SolverEffort> solver_effort_from_name(std::string_view name) { return from_name(kEfforts, name); }
const char* target_name(Target target) { return name_of(kTargets, target); }
const char* solver_effort_name(SolverEffort effort) { return name_of(kEfforts, effort); }
std::optional<ErrorModel> error_model_from_name(std::string_view name) { return from_name(kErrorModels, name); }
const char* error_model_name(ErrorModel model) { return name_of(kErrorModels, model); }
std::optional<ValidationStep> validation_step_from_name(std::string_view name) { return from_name(kSteps, name); }
const char* validation_step_name(ValidationStep step) { return name_of(kSteps, step); }
std::optional<LintProfile> lint_profile_from_name(std::string_view name) {
  for (const LintProfile profile : kLintProfiles)
    if (name == rule_profile_name(profile)) return profile;
  return std::nullopt;
}
const char* lint_profile_name(LintProfile profile) { return rule_profile_name(profile); }
const char* file_status_name(FileStatus status) { return name_of(kStatuses, status); }
std::optional<FileStatus> file_status_from_name(std::string_view name) { return from_name(kStatuses, name); }

}  // namespace gltf_pbr
