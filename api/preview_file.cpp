// Previewing files: the tool's `preview` and the library's preview_file.
#include <algorithm>

#include "api/files.hpp"
#include "core/error.hpp"
#include "rules/rule_set.hpp"
#include "validators/materials/materials.hpp"

namespace gltf_pbr {

DrawnPreview finish_preview(preview::PreviewResult result, const preview::PreviewOptions& options,
                            const std::string& name, nlohmann::json extra, const fs::path& out_dir) {
  if (drew_nothing(result)) throw InputError(name, "", kNothingToDraw);
  nlohmann::json report = preview::preview_report(result, options);
  report["input"] = name;
  if (extra.is_object()) report.update(extra);
  std::vector<fs::path> written = preview::write_preview(result, report, out_dir);
  return {std::move(result), std::move(report), std::move(written)};
}

DrawnPreview preview_one(const fs::path& input, const fs::path& out_dir, const preview::PreviewOptions& options,
                         bool allow_outside_uris, std::optional<LintProfile> lint) {
  const Asset asset = load_asset(input, {allow_outside_uris, nullptr, std::nullopt});
  preview::PreviewOptions drawing = options;
  nlohmann::json issues = nullptr;
  if (lint)
    drawing.on_converted = [&](const Asset& converted, DecodedImages& decoded) {
      issues = material_issues(asset, converted, lint, &decoded);
    };
  preview::PreviewResult result = preview::render_preview(asset, drawing);
  return finish_preview(std::move(result), options, input.string(), {{"material_issues", std::move(issues)}}, out_dir);
}

nlohmann::json material_issues(const Asset& input, const Asset& converted, std::optional<LintProfile> lint,
                               DecodedImages* decoded) {
  if (!lint) return nullptr;
  const RuleSet& rules = builtin_rules(*lint);
  MaterialCheckOptions materials_only;
  materials_only.textures = false;
  materials_only.decoded = decoded;
  auto issues_of = [&](const Asset& asset) {
    Report report;
    validate_materials(asset, rules, materials_only, report);
    apply_policy({}, report);
    nlohmann::json list = nlohmann::json::array();
    for (const Issue& issue : report.messages) {
      if (!issue.code.starts_with("PBR_")) continue;
      nlohmann::json entry{{"code", issue.code},
                           {"severity", severity_name(issue.severity)},
                           {"pointer", issue.pointer},
                           {"message", issue.message}};
      if (issue.count > 1) entry["count"] = issue.count;
      list.push_back(std::move(entry));
    }
    return list;
  };
  return {{"profile", lint_profile_name(*lint)}, {"before", issues_of(input)}, {"after", issues_of(converted)}};
}

}  // namespace gltf_pbr
