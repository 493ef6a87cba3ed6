// The names of the public enumerations, as the tool's options, its reports and the Python module
// spell them, and the library's version.
#include <array>
#include <utility>

#include "api/files.hpp"
#include "core/version.hpp"
#include "gltf_pbr/gltf_pbr.hpp"
#include "rules/rule_set.hpp"

namespace gltf_pbr {
namespace {

constexpr std::array<std::pair<Target, const char*>, 2> kTargets{{
    {Target::Metalness, "metalness"},
    {Target::Specular, "specular"},
}};
constexpr std::array<std::pair<SolverEffort, const char*>, 4> kEfforts{{
    {SolverEffort::Fast, "fast"},
    {SolverEffort::Balanced, "balanced"},
    {SolverEffort::Exact, "exact"},
    {SolverEffort::Reference, "reference"},
}};
constexpr std::array<std::pair<ErrorModel, const char*>, 2> kErrorModels{{
    {ErrorModel::NormalIncidence, "normal-incidence"},
    {ErrorModel::Appearance, "appearance"},
}};
constexpr std::array<std::pair<FileStatus, const char*>, 3> kStatuses{{
    {FileStatus::Converted, "converted"},
    {FileStatus::Copied, "copied"},
    {FileStatus::Failed, "failed"},
}};
constexpr std::array<std::pair<ValidationStep, const char*>, 4> kSteps{{
    {ValidationStep::Structure, "structure"},
    {ValidationStep::Materials, "materials"},
    {ValidationStep::Textures, "textures"},
    {ValidationStep::Meshes, "meshes"},
}};

template <typename Enum, std::size_t N>
std::optional<Enum> from_name(const std::array<std::pair<Enum, const char*>, N>& table, std::string_view name) {
  for (const auto& [value, value_name] : table)
    if (name == value_name) return value;
  return std::nullopt;
}
template <typename Enum, std::size_t N>
const char* name_of(const std::array<std::pair<Enum, const char*>, N>& table, Enum value) {
  for (const auto& [entry, entry_name] : table)
    if (entry == value) return entry_name;
  return "?";
}

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
