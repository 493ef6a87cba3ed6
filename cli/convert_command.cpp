// `gltf-pbr convert`: many files in parallel, each loaded once, converted, saved atomically.
#include <stdlib.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <thread>

#include "api/files.hpp"
#include "api/result_cache.hpp"
#include "cli/commands.hpp"
#include "cli/file_summary.hpp"
#include "cli/inputs.hpp"
#include "cli/isolate.hpp"
#include "cli/pipeline.hpp"
#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "core/image.hpp"
#include "core/text.hpp"

namespace gltf_pbr::cli {
namespace {

struct ConvertArgs {
  std::vector<std::string> inputs;
  std::string output, format, report, preview;
  ConversionArgs conversion;
  // The options bound straight to their field; target, solver, error model, metalness tolerance and
  // preview lint come from `conversion` and their names in run.
  ConvertFileOptions file;
  bool quiet = false, verbose = false, isolate = false;
  double file_timeout = 0;        // seconds, with --isolate; 0: none
  std::uint64_t file_memory = 0;  // MiB, with --isolate; 0: none
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  std::string preview_lint;  // empty: the material rules do not run
  bool no_gallery = false;
  PipelineArgs pipeline;
};

// Expands inputs (files, directories searched recursively) into jobs with output paths; inputs
// under the output folder are earlier outputs, left out and counted.
// `files` receives the input file of each job.
std::vector<ConvertJob> plan_jobs(const ConvertArgs& args, std::size_t& skipped_under_output,
                                  std::vector<InputFile>& files) {
  const fs::path output = args.output;
  const bool single_file_output = !args.file.replace_input && is_gltf_file(output) && !fs::is_directory(output);
  const GivenInputs inputs = all_inputs(args.inputs, args.pipeline);
  // One output file is left out of the inputs too, so `convert models -o models/all.glb` reruns.
  FoundInputs found = find_gltf_files(inputs, args.file.replace_input ? fs::path() : output);
  skipped_under_output = found.skipped_under_output;
  files = std::move(found.files);
  if (single_file_output && files.size() > 1)
    throw CLI::ValidationError(
        "--output", output.string() + " is one file, for " + std::to_string(files.size()) + " inputs: give a folder");
  std::vector<ConvertJob> jobs;
  for (const auto& [file, relative, key] : files) {
    fs::path target;
    if (args.file.replace_input) {
      target = file;
    } else if (single_file_output) {
      target = output;
    } else {
      target = output / relative;
      if (!args.format.empty()) target.replace_extension("." + args.format);
    }
    fs::path preview_folder;
    if (!args.preview.empty()) preview_folder = fs::path(args.preview) / fs::path(relative).replace_extension();
    jobs.push_back({file, target, preview_folder});
  }
  std::vector<fs::path> outputs, previews;
  for (const ConvertJob& job : jobs) {
    outputs.push_back(job.output);
    previews.push_back(job.preview_dir);
  }
  refuse_shared_outputs(files, outputs);
  if (!args.preview.empty())  // a preview folder is the file's path without its extension
    refuse_shared_outputs(files, previews, "rename one, or preview them in separate runs");
  return jobs;
}

std::string exact_text(double value) {  // every digit the double holds
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// The options a --isolate child takes from this run: everything that shapes a file's result.
std::vector<std::string> child_options(const ConvertArgs& args) {
  std::vector<std::string> options{"--target",
                                   args.conversion.target,
                                   "--solver",
                                   args.conversion.solver,
                                   "--error-model",
                                   args.conversion.error_model,
                                   "--specular-tolerance",
                                   exact_text(args.file.specular_tolerance),
                                   "--png-compression",
                                   std::to_string(args.file.png_compression),
                                   "--jpeg-quality",
                                   std::to_string(args.file.jpeg_quality),
                                   "--metalness-tolerance",
                                   exact_text(args.conversion.metalness_tolerance),
                                   "--error-samples",
                                   std::to_string(args.file.error_samples),
                                   "--max-image-pixels",
                                   std::to_string(max_image_pixels()),
                                   "--preview-size",
                                   std::to_string(args.file.preview_size),
                                   "--no-gallery"};  // the run writes the page once, at its end
  if (!args.preview_lint.empty()) options.push_back("--preview-lint=" + args.preview_lint);
  if (args.file.allow_outside_uris) options.push_back("--allow-outside-uris");
  if (!args.pipeline.cache.empty()) options.insert(options.end(), {"--cache", args.pipeline.cache});
  return options;
}

int run(const ConvertArgs& args) {
  if (args.output.empty() && !args.file.replace_input)
    throw CLI::ValidationError("--output", "give -o/--output, or --in-place");
  if (!args.preview_lint.empty() && args.preview.empty())
    throw CLI::ValidationError("--preview-lint", "checks what --preview draws: give --preview DIR too");
  if (args.file.replace_input && !args.pipeline.cache.empty())
    throw CLI::ValidationError("--cache", "--in-place replaces the inputs the cache is keyed by: give -o instead");
  ConvertFileOptions options = args.file;
  options.target = *target_from_name(args.conversion.target);  // CLI::IsMember checked the names
  options.solver = *solver_effort_from_name(args.conversion.solver);
  options.error_model = *error_model_from_name(args.conversion.error_model);
  options.metalness_tolerance = args.conversion.metalness_tolerance;
  if (!args.preview_lint.empty()) options.preview_lint = lint_profile_from_name(args.preview_lint);
  // Given or not: a --shard 0/1 run is the whole input, and still writes what merge-reports reads.
  const bool sharded = !args.pipeline.shard.empty();
  const Shard shard = sharded ? parse_shard(args.pipeline.shard) : Shard{};
  std::size_t skipped = 0;
  std::vector<InputFile> inputs;
  // The whole run is planned, and its outputs checked, before a shard takes its part: every shard
  // sees the same run, and a file's position is its place in it.
  const std::vector<ConvertJob> planned = plan_jobs(args, skipped, inputs);
  if (skipped && !args.quiet)
    std::fprintf(stderr, "skipped %zu .gltf/.glb files inside the output folder %s (earlier outputs)\n", skipped,
                 printable(args.output).c_str());
  const std::vector<std::size_t> positions = positions_in_shard(inputs, args.pipeline);
  std::vector<ConvertJob> jobs;
  for (const std::size_t position : positions) jobs.push_back(planned[position]);

  const RunReads reads{args.file.allow_outside_uris, args.pipeline.inputs_from, {}};
  std::vector<PlannedOutput> written{{args.report, "--report"}, {args.pipeline.results, "--results"}};
  for (const ConvertJob& job : jobs)
    if (!job.preview_dir.empty())
      for (const char* name : preview::kPreviewFiles) written.push_back({job.preview_dir / name, "--preview"});
  refuse_writing_over_inputs(inputs, written, reads);
  ResultsLog results_log(args.pipeline.results);
  std::optional<ResultCache> cache;  // with --isolate, each child keeps its file in the cache
  if (!args.pipeline.cache.empty() && !args.isolate) cache.emplace(args.pipeline.cache);
  std::optional<TemporaryFolder> scratch;  // the children's reports
  std::vector<nlohmann::json> child_caches(jobs.size());
  ConvertJobFunction in_child;
  if (args.isolate) {
    scratch.emplace("gltf-pbr-isolate-");
    in_child = [&, options = child_options(args), limits = ChildLimits{args.file_timeout, args.file_memory << 20}](
                   std::size_t job, const ConvertJob& convert_job) {
      return convert_in_child(convert_job, options, limits, scratch->path(), job, &child_caches[job]);
    };
  }
  Progress progress(jobs.size(), "converting");
  const std::vector<FileResult> results = convert_batch(
      jobs, options, args.jobs,
      [&](std::size_t job, const FileResult& result) {
        nlohmann::json line = file_json(result);
        line["position"] = positions[job];
        results_log.write(line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
        const bool show = !args.quiet || result.status == FileStatus::Failed;
        progress.done(show ? file_summary(result, args.verbose) : "");
      },
      cache ? &*cache : nullptr, in_child);
  const auto failed =
      std::count_if(results.begin(), results.end(), [](const FileResult& r) { return r.status == FileStatus::Failed; });
  if (!args.report.empty()) {
    nlohmann::json report = run_json(results, options);
    if (cache) {
      report["cache"] = cache->stats_json();
      report["cache"]["assetsLoaded"] = work_counters().assets_loaded.load();
    } else if (args.isolate && !args.pipeline.cache.empty()) {
      report["cache"] = sum_of_counts(child_caches);
    }
    if (sharded) {  // what merge-reports needs to put the shards back together
      report["shard"] = {{"index", shard.index}, {"count", shard.count}, {"files", planned.size()}};
      for (std::size_t i = 0; i < positions.size(); ++i) report["files"][i]["position"] = positions[i];
    }
    write_atomically(args.report, json_text(report));
  }
  if (!args.preview.empty() && !args.no_gallery) write_gallery_page(args.preview, args.quiet);
  if (!args.quiet)
    std::fprintf(
        stderr, "%s: %zu converted or copied%s, %zu failed\n", counted(results.size(), "file").c_str(),
        results.size() - static_cast<size_t>(failed),
        cache ? (" (" + std::to_string(cache->hits()) + " from the cache)").c_str()
        : args.isolate && !args.pipeline.cache.empty()
            ? (" (" + std::to_string(sum_of_counts(child_caches).value("hits", 0)) + " from the cache)").c_str()
            : "",
        static_cast<size_t>(failed));
  return failed ? kSomeFilesFailed : kAllDone;
}

constexpr const char* kConvertHelp = R"(Convert KHR_materials_pbrSpecularGlossiness materials to core metal-rough.
Factors are solved analytically, textures texel by texel; the report gives each material's
ΔE2000 error (diffuse weight and F0) against the time it cost. Inputs are never overwritten
(unless --in-place); every output is written to a temporary file and renamed.
Exit codes: 0 all files converted, 1 some files failed, 2 bad usage, 3 a report or --results could
not be written.)";

void declare_options(CLI::App& cmd, ConvertArgs& args) {
  cmd.add_option("inputs", args.inputs, ".gltf/.glb files or directories (searched recursively)");
  cmd.add_option("-o,--output", args.output,
                 "output file (one input; .gltf or .glb picks the format) or directory (mirrors the inputs; "
                 "a name ending in .gltf or .glb is a file, so several inputs need a folder)");
  cmd.add_option("--format", args.format, "output format for directory outputs (default: as the input)")
      ->check(CLI::IsMember({"gltf", "glb"}));
  cmd.add_flag("--in-place", args.file.replace_input, "replace each input with its conversion (atomically)");
  add_conversion_options(cmd, args.conversion);
  cmd.add_option("--specular-tolerance", args.file.specular_tolerance, "ΔE2000 (p95) the metalness fit may miss by")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd.add_option("--preview", args.preview,
                 "also draw each file before and after (gltf-pbr preview) into DIR/<input path without extension>/, "
                 "and write DIR/index.html, a page comparing them all (gltf-pbr gallery)");
  cmd.add_option("--preview-size", args.file.preview_size, "--preview: image width and height in pixels")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
  cmd.add_flag("--preview-lint{tolerant}", args.preview_lint,
               "--preview: also run the material rules (validate --only materials) on each input and its output; "
               "their PBR_* issues go into the preview's report.json and the gallery page (=strict for the strict "
               "profile)")
      ->check(CLI::IsMember({"tolerant", "strict"}));
  cmd.add_flag("--no-gallery", args.no_gallery, "--preview: leave DIR/index.html as it is");
  cmd.add_option("--report", args.report, "write the JSON report (per file, per material: error, texels, time)");
  cmd.add_option("--png-compression", args.file.png_compression,
                 "deflate level 0-9 of baked PNG textures (libdeflate: 1 fast, 9 smallest; images of at most 64 KiB "
                 "of rows always take 9)")
      ->check(CLI::Range(0, 9))
      ->capture_default_str();
  cmd.add_option("--jpeg-quality", args.file.jpeg_quality,
                 "quality 1-100 of base colours baked from JPEG diffuse textures")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd.add_option("--error-samples", args.file.error_samples,
                 "texels sampled per texture for the error statistics (0: all)")
      ->capture_default_str();
  add_batch_options(cmd, "converted", args.jobs, args.file.allow_outside_uris);
  CLI::Option* isolate =
      cmd.add_flag("--isolate", args.isolate,
                   "convert each file in a child process: a crash, a hang (--file-timeout) or a runaway allocation "
                   "(--file-memory) fails that file and the run goes on (about 20 ms more per file)");
  // Limits only a child process can be held to: refused without --isolate rather than ignored.
  cmd.add_option("--file-timeout", args.file_timeout, "with --isolate: seconds a file may take (0: no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str()
      ->needs(isolate);
  cmd.add_option("--file-memory", args.file_memory,
                 "with --isolate: MiB of resident memory a file's child may use (0: no limit)")
      ->capture_default_str()
      ->needs(isolate);
  add_pipeline_options(cmd, args.pipeline);
  cmd.add_flag("-q,--quiet", args.quiet, "print only failures");
  cmd.add_flag("-v,--verbose", args.verbose, "print every material, not only those with notes");
}

}  // namespace

std::function<int()> add_convert_command(CLI::App& app) {
  return add_subcommand<ConvertArgs>(app, "convert", kConvertHelp, declare_options, run);
}

}  // namespace gltf_pbr::cli
