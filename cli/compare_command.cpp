// `gltf-pbr compare`: the error a viewer sees in a converted asset against its legacy original.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/inputs.hpp"
#include "converter/evaluate.hpp"
#include "core/error.hpp"
#include "core/text.hpp"

namespace gltf_pbr::cli {
namespace {

struct CompareArgs {
  std::string legacy, converted, viewer = "core";
  size_t error_samples = size_t{1} << 16;
  bool allow_outside_uris = false;
};

nlohmann::json stats(const ErrorStats& s) { return {{"mean", s.mean}, {"p95", s.p95}, {"max", s.max}}; }

// An input that cannot be read or compared fails the run (exit 1: InputErrors::FailTheInput).
int run(const CompareArgs& args) {
  LoadOptions load;
  load.allow_outside_uris = args.allow_outside_uris;
  const Asset legacy = load_asset(args.legacy, load), converted = load_asset(args.converted, load);
  const auto materials = compare_conversion(legacy, converted, args.viewer == "full" ? Viewer::Full : Viewer::CoreOnly,
                                            args.error_samples);
  nlohmann::json out = {{"legacy", args.legacy}, {"converted", args.converted}, {"viewer", args.viewer}};
  nlohmann::json list = nlohmann::json::array();
  double sum_mean = 0, worst = 0;
  for (const auto& m : materials) {
    list.push_back({{"index", m.index},
                    {"name", m.name},
                    {"samples", m.samples},
                    {"deltaE2000", {{"diffuse", stats(m.error.diffuse)}, {"f0", stats(m.error.f0)}}}});
    sum_mean += 0.5 * (m.error.diffuse.mean + m.error.f0.mean);
    worst = std::max(worst, m.error.worst());
  }
  out["materials"] = list;
  out["summary"] = {
      {"materials", materials.size()},
      {"meanOfMaterialMeans",
       materials.empty() ? nlohmann::json(nullptr) : nlohmann::json(sum_mean / static_cast<double>(materials.size()))},
      {"worst", materials.empty() ? nlohmann::json(nullptr) : nlohmann::json(worst)}};  // null: nothing measured
  write_stdout(json_text(out));
  return kAllDone;
}

constexpr const char* kCompareHelp =
    R"(Print, as JSON, the ΔE2000 error (diffuse weight and F0 at normal incidence) that a viewer sees in
CONVERTED against the spec-gloss materials of LEGACY, material by material (same indices), on the
texels convert bakes: both materials' textures on their larger size, resampled to it where they differ.
Works on any converter's output, ours or another tool's; on convert's own it gives convert's figures.
A material left as spec-gloss is measured as a viewer shows it: by its core fallback, since neither
viewer reads the archived extension (convert's report says null for it: it converted nothing).
Exit codes: 0 compared, 1 an input could not be read or compared, 2 bad usage, 3 the output cannot be written.)";

void declare_options(CLI::App& cmd, CompareArgs& args) {
  cmd.add_option("legacy", args.legacy, "the spec-gloss original")->required();
  cmd.add_option("converted", args.converted, "its conversion")->required();
  cmd.add_option("--viewer", args.viewer,
                 "core: baseColor/metallic/roughness only; full: also KHR_materials_specular and KHR_materials_ior")
      ->check(CLI::IsMember({"core", "full"}))
      ->capture_default_str();
  cmd.add_option("--error-samples", args.error_samples,
                 "texels sampled per material for the error statistics, as convert samples them (0: all)")
      ->capture_default_str();
  cmd.add_flag("--allow-outside-uris", args.allow_outside_uris, "read buffer/image URIs outside the assets' folders");
  add_image_limit_option(cmd);
}

}  // namespace

std::function<int()> add_compare_command(CLI::App& app) {
  return add_subcommand<CompareArgs>(app, "compare", kCompareHelp, declare_options, run, InputErrors::FailTheInput);
}

}  // namespace gltf_pbr::cli
