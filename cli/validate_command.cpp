// `gltf-pbr validate`: many files in parallel, one Khronos-schema report per file plus a summary,
// as JSON, text or SARIF; --fail-on turns findings into the exit code.
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "api/result_cache.hpp"
#include "cli/commands.hpp"
#include "cli/inputs.hpp"
#include "cli/pipeline.hpp"
#include "cli/validation_formats.hpp"
#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "core/image.hpp"
#include "core/parallel.hpp"
#include "core/text.hpp"
#include "core/version.hpp"
#include "rules/rule_set.hpp"
#include "validators/materials/materials.hpp"  // heat_map_stem
#include "validators/validate.hpp"

namespace gltf_pbr::cli {
namespace {

// Whether two descriptors are one file: a terminal, or a log both are redirected to.
bool same_file(int a, int b) {
  struct stat first {};
  struct stat second {};
  return ::fstat(a, &first) == 0 && ::fstat(b, &second) == 0 && first.st_dev == second.st_dev &&
         first.st_ino == second.st_ino;
}

struct ValidateArgs {
  std::vector<std::string> inputs;
  std::string output, format = "text", config, fail_on = "error", heatmaps,
                      profile = rule_profile_name(kDefaultLintProfile);
  PipelineArgs pipeline;
  std::vector<std::string> only;
  bool allow_outside = false, quiet = false, no_self_intersections = false;
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
};

std::vector<std::string> profile_names() {
  std::vector<std::string> names;
  for (const LintProfile profile : kLintProfiles) names.emplace_back(rule_profile_name(profile));
  return names;
}

bool fails(const Report& report, Severity fail_on) {
  for (const Issue& issue : report.messages)
    if (static_cast<int>(issue.severity) <= static_cast<int>(fail_on)) return true;
  return false;
}

// A file's line in the summary (and in --results).
nlohmann::ordered_json summary_entry(const Report& report, Severity fail_on) {
  return {{"uri", report.uri},
          {"numErrors", report.count(Severity::Error)},
          {"numWarnings", report.count(Severity::Warning)},
          {"numInfos", report.count(Severity::Information)},
          {"numHints", report.count(Severity::Hint)},
          {"failed", fails(report, fail_on)}};
}

// Where a report folder's summary goes: shards writing into one folder keep a summary each.
fs::path summary_path(const fs::path& folder, bool sharded, const Shard& shard) {
  return folder / (sharded ? "summary-shard" + std::to_string(shard.index) + ".json" : std::string("summary.json"));
}

nlohmann::ordered_json summary_json(const std::vector<Report>& reports, Severity fail_on) {
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  std::size_t totals[4] = {0, 0, 0, 0}, failing = 0;
  for (const Report& report : reports) {
    for (int s = 0; s < 4; ++s) totals[s] += report.count(static_cast<Severity>(s));
    failing += fails(report, fail_on);
    files.push_back(summary_entry(report, fail_on));
  }
  return {{"tool", "gltf-pbr"},
          {"version", tool_version()},
          {"files", reports.size()},
          {"failing", failing},
          {"failOn", severity_name(fail_on)},
          {"numErrors", totals[0]},
          {"numWarnings", totals[1]},
          {"numInfos", totals[2]},
          {"numHints", totals[3]},
          {"reports", std::move(files)}};
}

// What every file's report depends on besides the file and those it names (ResultCache::key).
std::string run_settings(const ValidateArgs& args, const ValidateOptions& options) {
  std::string text = std::string("validate ") + tool_version() + " steps";
  for (const ValidationStep step : options.steps) text += std::string(" ") + validation_step_name(step);
  text += std::string(" self-intersections ") + (options.self_intersections ? "on" : "off") + " allow-outside " +
          (options.allow_outside_uris ? "on" : "off") + " max-image-pixels " + std::to_string(max_image_pixels()) +
          " profile " + args.profile + "\n" + builtin_rules_text();
  if (!args.config.empty()) {  // its text, not its name: an edited config is another run
    const std::optional<Bytes> config = read_file(args.config);
    if (!config) throw InputError(args.config, "", "cannot read the config file: " + unreadable_reason(args.config));
    text += "\nconfig\n" + std::string(config->begin(), config->end());
  }
  return text;
}

int run(const ValidateArgs& args) {
  if (!args.pipeline.cache.empty() && !args.heatmaps.empty())
    throw CLI::ValidationError("--cache", "the cache does not keep heat maps: give --cache or --heatmaps");
  RuleSet rules = builtin_rules(*lint_profile_from_name(args.profile));  // CLI11 checked the name
  IssuePolicy policy;
  if (!args.config.empty()) apply_user_config(args.config, rules, policy);
  ValidateOptions options;
  if (!args.only.empty()) {
    options.steps.clear();
    for (const std::string& step : args.only) options.steps.insert(*validation_step_from_name(step));  // CLI11 checked
  }
  options.heatmaps_dir = args.heatmaps;
  options.allow_outside_uris = args.allow_outside;
  options.self_intersections = !args.no_self_intersections;
  const Severity fail_on = *severity_from_name(args.fail_on);

  const bool sharded = !args.pipeline.shard.empty();
  const Shard shard = sharded ? parse_shard(args.pipeline.shard) : Shard{};
  const std::vector<InputFile> found = find_gltf_files(all_inputs(args.inputs, args.pipeline)).files;
  const std::vector<std::size_t> positions = positions_in_shard(found, args.pipeline);
  std::vector<InputFile> files;
  for (const std::size_t position : positions) files.push_back(found[position]);
  const bool report_folder = args.format == "json" && !args.output.empty();
  std::vector<fs::path> report_paths;
  if (report_folder) {
    // A folder: <input path>.report.json per file, as the reference names them, and summary.json.
    for (const InputFile& file : files)
      report_paths.push_back(fs::path(args.output) / (file.relative.string() + ".report.json"));
    refuse_shared_outputs(files, report_paths);
  }
  const bool colour = args.output.empty() && ::isatty(STDOUT_FILENO) && !std::getenv("NO_COLOR");
  std::vector<Report> reports(files.size());
  // Nothing is written (folders included) before the run is known not to write over its inputs.
  const RunReads reads{args.allow_outside, args.pipeline.inputs_from, args.config};
  std::vector<PlannedOutput> written{{args.pipeline.results, "--results"}};
  if (report_folder) {
    for (const fs::path& path : report_paths) written.push_back({path, "--output"});
    written.push_back({summary_path(args.output, sharded, shard), "--output"});
  } else {
    written.push_back({args.output, "--output"});
  }
  // Heat maps go under each input's relative folder (validate_one below), named as they are written:
  // a folder's planned names are its inputs' heat maps.
  if (!args.heatmaps.empty()) {
    // Two inputs whose heat maps would take the same names (a/t.gltf and b/t.gltf given as files).
    std::vector<fs::path> heat_map_names;
    for (const InputFile& file : files)
      heat_map_names.push_back(fs::path(args.heatmaps) / file.relative.parent_path() /
                               (file.file.stem().string() + "-material*.png"));
    refuse_shared_outputs(files, heat_map_names);
    std::map<fs::path, std::set<std::string>> stems_by_folder;
    for (const InputFile& file : files)
      stems_by_folder[fs::path(args.heatmaps) / file.relative.parent_path()].insert(file.file.stem().string());
    for (auto& [folder, stems] : stems_by_folder)
      written.push_back({folder, "--heatmaps", [stems = std::move(stems)](const std::string& name) {
                           const std::optional<std::string> stem = heat_map_stem(name);
                           return stem && stems.count(*stem) > 0;
                         }});
  }
  refuse_writing_over_inputs(found, written, reads);
  if (!args.heatmaps.empty()) {
    std::error_code error;
    fs::create_directories(args.heatmaps, error);
    if (error || !fs::is_directory(args.heatmaps))
      throw CLI::ValidationError("--heatmaps", args.heatmaps + ": cannot create the folder (" + error.message() + ")");
  }
  std::optional<ResultCache> cache;
  if (!args.pipeline.cache.empty()) cache.emplace(args.pipeline.cache);
  ResultsLog results_log(args.pipeline.results);
  const std::string settings = cache ? run_settings(args, options) : "";
  // A file's report from the cache when it holds one, else validated and stored.
  const auto report_of = [&](const InputFile& file, const ValidateOptions& file_options, bool& restored) {
    restored = false;
    const std::string name = file.file.string();
    const std::optional<std::string> key =
        cache
            ? cache->key(file.file, settings + "\ninput " + file.file.extension().string(), options.allow_outside_uris)
            : std::nullopt;
    const auto readable = [](const nlohmann::json& entry) {
      return entry.is_object() && entry.contains("report") && entry["report"].is_string() &&
             entry.contains("materialNames") && entry["materialNames"].is_array();
    };
    if (key)
      if (const std::optional<nlohmann::json> entry = cache->restore(*key, {}, readable)) try {
          Report report = report_from_json(nlohmann::ordered_json::parse(entry->at("report").get<std::string>()));
          report.uri = name;
          report.material_names = entry->at("materialNames").get<std::vector<std::string>>();
          restored = true;
          return report;
        } catch (const std::exception&) {
          cache->discard(*key);  // not a report this version wrote: validated again below
        }
    Report report = validate_file(file.file, name, rules, policy, file_options);
    // A report with IO_ERROR may say a step ran out of memory or time: kept only without one.
    const bool complete = std::none_of(report.messages.begin(), report.messages.end(),
                                       [](const Issue& issue) { return issue.code == "IO_ERROR"; });
    if (key && complete)
      // As text: the entry is a JSON object of sorted keys, and the report's keep their order.
      cache->store(*key, {{"report", report_to_json(report).dump()}, {"materialNames", report.material_names}}, {});
    else if (key)
      cache->leave_out(*key);
    return report;
  };
  // The text report on standard output opens each file with the same line: not repeated on
  // standard error when both reach one place (a terminal, a log taking 2>&1).
  const bool line_in_report = args.format == "text" && args.output.empty() && same_file(STDOUT_FILENO, STDERR_FILENO);
  Progress progress(files.size(), "validating");
  const auto validate_one = [&](std::int64_t index) {
    const auto i = static_cast<std::size_t>(index);
    // Heat maps go under the input's own relative folder, so a/Box.gltf and b/Box.gltf keep theirs.
    ValidateOptions file_options = options;
    if (!options.heatmaps_dir.empty())
      file_options.heatmaps_dir = options.heatmaps_dir / files[i].relative.parent_path();
    const auto start = std::chrono::steady_clock::now();
    bool restored = false;
    reports[i] = report_of(files[i], file_options, restored);
    const Report& report = reports[i];
    // The line, unlike the summary, says what this run spent: shards merge into the unsharded summary
    // byte for byte only while it holds no times.
    nlohmann::ordered_json line_entry = summary_entry(report, fail_on);
    line_entry["position"] = positions[i];
    if (restored) line_entry["cached"] = true;
    line_entry["timeMs"] = {
        {"total", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()}};
    results_log.write(line_entry.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    std::ostringstream line;
    if (!line_in_report && (!args.quiet || fails(report, fail_on)))
      line << printable(report.uri) << ": " << report.count(Severity::Error) << " errors, "
           << report.count(Severity::Warning) << " warnings, " << report.count(Severity::Information) << " infos, "
           << report.count(Severity::Hint) << " hints\n";
    progress.done(line.str());
  };
  ThreadPool::shared().run(static_cast<std::int64_t>(files.size()), validate_one, args.jobs);

  nlohmann::ordered_json summary = summary_json(reports, fail_on);
  if (sharded) {  // where each file stands in the whole run, as convert's shard reports say
    summary["shard"] = {{"index", shard.index}, {"count", shard.count}, {"files", found.size()}};
    for (std::size_t i = 0; i < positions.size(); ++i) summary["reports"][i]["position"] = positions[i];
  }
  if (cache) {
    summary["cache"] = cache->stats_json();
    summary["cache"]["assetsLoaded"] = work_counters().assets_loaded.load();
  }
  if (args.format == "sarif") {
    write_output(args.output, json_text(sarif_log(reports, rules)));
  } else if (args.format == "json") {
    if (args.output.empty()) {
      // One report as the Khronos validator prints it; several with the summary around them.
      if (reports.size() == 1) {
        write_stdout(report_json_text(reports.front()));
      } else {
        nlohmann::ordered_json all = summary;
        all["reports"] = nlohmann::ordered_json::array();
        for (const Report& report : reports) all["reports"].push_back(report_to_json(report));
        write_stdout(json_text(all));
      }
    } else {
      for (std::size_t i = 0; i < files.size(); ++i) write_atomically(report_paths[i], report_json_text(reports[i]));
      write_atomically(summary_path(args.output, sharded, shard), json_text(summary));
    }
  } else {
    std::string text;  // -q: only the files that fail
    for (const Report& report : reports)
      if (!args.quiet || fails(report, fail_on)) text += report_text(report, colour);
    write_output(args.output, text);
  }
  if (!args.quiet)
    std::fprintf(stderr, "%s%s: %zu with issues at or above %s\n", counted(reports.size(), "file").c_str(),
                 cache ? (" (" + std::to_string(cache->hits()) + " from the cache)").c_str() : "",
                 summary["failing"].get<std::size_t>(), severity_name(fail_on));
  return summary["failing"].get<std::size_t>() > 0 ? kSomeFilesFailed : kAllDone;
}

constexpr const char* kValidateHelp =
    R"(Validate glTF files: structure (the Khronos glTF-Validator's issue codes), physically implausible
materials (PBR_*: F0, albedo, metalness, from factors and texel by texel), textures (IMAGE_*) and
meshes (MESH_*, CGAL; Draco meshes included). Rules are data (rules/*.json, built in); --config
overrides them. Exit codes: 0 no file has issues at or above --fail-on, 1 some do, 2 bad usage or a bad
config, 3 a report could not be written.)";

void declare_options(CLI::App& cmd, ValidateArgs& args) {
  cmd.add_option("inputs", args.inputs, ".gltf/.glb files or directories (searched recursively)");
  cmd.add_option("-f,--format", args.format,
                 "text: for people, grouped by material; json: the Khronos validator's report schema; sarif: "
                 "SARIF 2.1.0 for code scanning")
      ->check(CLI::IsMember({"text", "json", "sarif"}))
      ->capture_default_str();
  cmd.add_option("-o,--output", args.output,
                 "write to this file (text, sarif) or folder (json: one <input>.report.json per file + "
                 "summary.json) instead of stdout");
  cmd.add_option("--config", args.config,
                 "YAML or JSON config in the Khronos validator's shape: max-issues, ignore, only, override "
                 "(code: 0-3); and thresholds: {CODE: {name: number}}");
  cmd.add_option("--profile", args.profile,
                 "how hard the material rules judge: tolerant warns where a value is clearly wrong for what "
                 "renders, strict where it leaves the calibrated ranges (rules/materials.json holds both); "
                 "--config thresholds apply on top")
      ->check(CLI::IsMember(profile_names()))
      ->capture_default_str();
  cmd.add_option("--only", args.only, "run only these steps (comma-separated or repeated)")
      ->allow_extra_args(false)
      ->delimiter(',')
      ->check(CLI::IsMember({"structure", "materials", "textures", "meshes"}));
  cmd.add_option("--fail-on", args.fail_on, "lowest severity that makes the exit code 1")
      ->check(CLI::IsMember({"error", "warning", "info", "hint"}))
      ->capture_default_str();
  cmd.add_option("--heatmaps", args.heatmaps,
                 "write one PNG per failing texture showing where it fails, under DIR/<the input's relative folder>/");
  cmd.add_flag("--no-self-intersections", args.no_self_intersections,
               "skip the self-intersection mesh check (the costliest)");
  add_batch_options(cmd, "validated", args.jobs, args.allow_outside);
  add_pipeline_options(cmd, args.pipeline);
  cmd.add_flag("-q,--quiet", args.quiet, "print only files that fail");
}

}  // namespace

std::function<int()> add_validate_command(CLI::App& app) {
  return add_subcommand<ValidateArgs>(app, "validate", kValidateHelp, declare_options, run);
}

}  // namespace gltf_pbr::cli
