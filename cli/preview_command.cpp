// `gltf-pbr preview IN -o DIR`: before/after images, difference map, sheet and a JSON report
// (the renderer is preview/).
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <optional>
#include <sstream>
#include <thread>

#include "api/files.hpp"
#include "api/result_cache.hpp"
#include "cli/commands.hpp"
#include "cli/inputs.hpp"
#include "cli/pipeline.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "core/parallel.hpp"
#include "core/text.hpp"
#include "core/version.hpp"
#include "preview/gallery.hpp"

namespace gltf_pbr::cli {
namespace {

std::string peak_text(const nlohmann::json& bytes) {
  if (!bytes.is_number()) return "not measured";
  return std::to_string(static_cast<long long>(bytes.get<double>() / (1 << 20))) + " MiB";
}

struct PreviewArgs {
  std::string input, output, environment, camera = "auto", brdf = "ggx", legacy_reading = "a", tone_map = "neutral";
  ConversionArgs conversion;
  int size = 512, width = 0, height = 0;
  double yaw = 35, pitch = 20, fov = 40;
  float exposure = 1.0f;
  bool no_sun = false, grid = false, allow_outside = false, quiet = false, no_gallery = false;
  std::string cache;
  std::string lint;  // empty: the material rules do not run
  std::vector<float> albedo{0.9f, 0.6f, 0.2f};
  int grid_count = 5;
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
};

// What a file's preview depends on besides the file and those it names (ResultCache::key): every
// option, the environment map's bytes, the image limit, the version and the input's name, which
// the report holds.
std::string settings(const PreviewArgs& args, const preview::PreviewOptions& options, const ResultCache& cache,
                     const fs::path& input) {
  std::ostringstream text;
  text.precision(17);
  text << "preview " << tool_version() << " size " << options.width << "x" << options.height << " yaw " << args.yaw
       << " pitch " << args.pitch << " fov " << args.fov << " camera " << args.camera << " brdf " << args.brdf
       << " legacy-reading " << args.legacy_reading << " tone-map " << args.tone_map << " exposure " << args.exposure
       << " sun " << !args.no_sun << " target " << args.conversion.target << " solver " << args.conversion.solver
       << " error-model " << args.conversion.error_model << " metalness-tolerance "
       << args.conversion.metalness_tolerance << " max-image-pixels " << max_image_pixels() << " allow-outside "
       << args.allow_outside << " lint " << (args.lint.empty() ? "off" : args.lint) << " env ";
  // The path too: the report names it.
  if (!args.environment.empty())
    text << args.environment << " " << cache.digest(args.environment).value_or("unreadable");
  text << "\ninput " << input.string();
  return text.str();
}

// The line a drawn preview prints: its figures, its G-buffers' size and the process's peak.
std::string drawn_line(const std::string& name, const DrawnPreview& drawn, const fs::path& output) {
  const preview::PreviewResult& result = drawn.result;
  const nlohmann::json& report = drawn.report;
  char figures[512];
  std::snprintf(figures, sizeof figures,
                "FLIP mean %.3f; ΔE2000 mean %.2f, p95 %.2f; RMS %.1f dB; G-buffer %d B/px after, %d B/px before",
                result.metrics.flip_mean, result.metrics.delta_e_mean, result.metrics.delta_e_p95,
                result.metrics.rms_db, report["gbuffer"]["after"]["bytes_per_pixel"].get<int>(),
                report["gbuffer"]["before"]["bytes_per_pixel"].get<int>());
  return printable(name) + ": " + figures + "; process peak " + peak_text(report["memory"]["process_peak_rss_bytes"]) +
         " -> " + printable(output.string()) + "\n";
}

struct CachedPreview {
  bool restored = false;  // from the cache, not drawn
  std::string line;       // what to print of it unless quiet
};

// One file's preview into `output`: restored when the cache holds it, else drawn and kept there.
// Throws for an input that cannot be drawn.
CachedPreview preview_with_cache(const PreviewArgs& args, const preview::PreviewOptions& options, const fs::path& input,
                                 const fs::path& output, ResultCache* cache) {
  std::optional<std::string> key;
  if (cache) {
    key = cache->key(input, settings(args, options, *cache, input), args.allow_outside);
    const fs::path roots[] = {output};
    if (key && cache->restore(*key, roots))
      return {true, printable(input.string()) + ": restored from the cache into " + printable(output.string()) + "\n"};
  }
  const std::optional<LintProfile> lint =
      args.lint.empty() ? std::nullopt : lint_profile_from_name(args.lint);  // CLI::IsMember checked the name
  std::optional<DrawnPreview> drawn;
  try {
    drawn = preview_one(input, output, options, args.allow_outside, lint);
  } catch (...) {
    if (key) cache->leave_out(*key);
    throw;
  }
  // A preview drawn without a texture it could not decode (memory, a damaged file) is not kept.
  if (key && drawn->result.scene.warnings.empty()) {
    const ResultCache::Outputs outputs[] = {{output, drawn->written}};
    cache->store(*key, {{"report", drawn->report}}, outputs);
  } else if (key) {
    cache->leave_out(*key);
  }
  return {false, drawn_line(input.string(), *drawn, output)};
}

// The files the previews in `folders` will write.
std::vector<PlannedOutput> preview_outputs(const std::vector<fs::path>& folders) {
  std::vector<PlannedOutput> written;
  for (const fs::path& folder : folders)
    for (const char* name : preview::kPreviewFiles) written.push_back({folder / name, "--output"});
  return written;
}

// Removes the preview files of an earlier run from `folder`, only where the gallery page would list
// them (preview::lists_a_preview). Whether any was.
bool remove_earlier_previews(const fs::path& folder) {
  if (!preview::lists_a_preview(folder)) return false;
  std::error_code ec;
  bool removed = false;
  for (const char* name : preview::kPreviewFiles) removed = fs::remove(folder / name, ec) || removed;
  return removed;
}

// `preview DIR -o OUT`: every .gltf and .glb under DIR, each into OUT/<its path without the
// extension> (as convert --preview names them), -j files at once on the one pool; a file that
// cannot be drawn is reported and the rest go on; one gallery page at the end.
int run_folder(const PreviewArgs& args, preview::PreviewOptions options) {
  const FoundInputs found = find_gltf_files(GivenInputs{{args.input}, {}}, args.output);
  if (!options.environment.empty())  // read and prefiltered once for every file
    options.loaded_environment =
        std::make_shared<const preview::Environment>(preview::load_environment(options.environment));
  std::vector<fs::path> outputs;
  for (const InputFile& file : found.files)
    outputs.push_back(fs::path(args.output) / fs::path(file.relative).replace_extension());
  refuse_shared_outputs(found.files, outputs, "rename one, or preview them in separate runs");
  refuse_writing_over_inputs(found.files, preview_outputs(outputs), RunReads{args.allow_outside, {}, {}});
  std::optional<ResultCache> cache;
  if (!args.cache.empty()) cache.emplace(args.cache);
  std::atomic<std::size_t> restored{0}, failed{0};
  {
    Progress progress(found.files.size(), "drawn");
    ThreadPool::shared().run(
        static_cast<std::int64_t>(found.files.size()),
        [&](std::int64_t index) {
          const auto i = static_cast<std::size_t>(index);
          std::string line;
          try {
            const CachedPreview done =
                preview_with_cache(args, options, found.files[i].file, outputs[i], cache ? &*cache : nullptr);
            restored += done.restored;
            if (!args.quiet) line = done.line;
          } catch (const std::exception& e) {
            ++failed;
            // An earlier run's previews of this input no longer show it: the gallery page below
            // must not list them as if they did.
            const bool removed = remove_earlier_previews(outputs[i]);
            const std::string name = found.files[i].file.string(), what = e.what();
            line = printable(what.rfind(name, 0) == 0 ? what : name + ": " + what) +
                   (removed ? " (its earlier previews removed)" : "") + "\n";  // errors even when quiet
          }
          progress.done(line);
        },
        args.jobs);
  }
  const std::size_t drawn = found.files.size() - restored - failed;
  if (!args.quiet)
    std::fprintf(stderr, "%s into %s: %zu drawn, %zu from the cache, %zu failed\n",
                 counted(found.files.size(), "preview").c_str(), printable(args.output).c_str(), drawn, restored.load(),
                 failed.load());
  if (!args.no_gallery) write_gallery_page(args.output, args.quiet);
  return failed ? kSomeFilesFailed : kAllDone;
}

int run(const PreviewArgs& args) {
  preview::PreviewOptions options;
  options.width = args.width > 0 ? args.width : args.size;
  options.height = args.height > 0 ? args.height : args.size;
  options.yaw_degrees = args.yaw;
  options.pitch_degrees = args.pitch;
  options.fov_y_degrees = args.fov;
  options.environment = args.environment;
  options.lighting.lobe = args.brdf == "blinn-phong" ? SpecularLobe::BlinnPhong : SpecularLobe::Ggx;
  options.lighting.legacy_reading_b = args.legacy_reading == "b";
  options.lighting.tone_map = args.tone_map == "aces"    ? preview::ToneMap::Aces
                              : args.tone_map == "clamp" ? preview::ToneMap::Clamp
                                                         : preview::ToneMap::KhronosPbrNeutral;
  options.lighting.exposure = args.exposure;
  options.lighting.sun = !args.no_sun;
  options.convert.target = *target_from_name(args.conversion.target);  // CLI::IsMember checked the names
  options.convert.solver = solver_preset(*solver_effort_from_name(args.conversion.solver),
                                         *error_model_from_name(args.conversion.error_model));
  options.convert.metalness_tolerance = args.conversion.metalness_tolerance;
  if (args.camera != "auto") {
    if (args.camera == "gltf") {
      options.gltf_camera = 0;
    } else {
      try {
        options.gltf_camera = std::stoi(args.camera);
      } catch (const std::exception&) {
        std::fprintf(stderr, "gltf-pbr preview: --camera takes auto, gltf or a camera number\n");
        return kBadUsage;
      }
    }
  }
  if (args.input.empty() && !args.grid) {
    std::fprintf(stderr, "gltf-pbr preview: give an input file or folder, or --grid\n");
    return kBadUsage;
  }
  if (!args.cache.empty() && args.grid) {
    std::fprintf(stderr, "gltf-pbr preview: --cache keeps files' previews; --grid draws none\n");
    return kBadUsage;
  }
  if (!args.lint.empty() && args.grid) {
    std::fprintf(stderr, "gltf-pbr preview: --lint checks an asset's materials; --grid draws spheres, not an asset\n");
    return kBadUsage;
  }
  if (args.grid) {
    preview::GridOptions grid;
    grid.albedo = glm::vec3(args.albedo[0], args.albedo[1], args.albedo[2]);
    grid.rows = grid.columns = args.grid_count;
    grid.cell = std::max(16, std::min(options.width, options.height) / args.grid_count);
    const nlohmann::json grid_report = {
        {"grid", {{"albedo_linear", args.albedo}, {"rows", "metalness 0..1"}, {"columns", "roughness 0..1"}}}};
    const DrawnPreview drawn =
        finish_preview(preview::render_grid(grid, options), options, "grid", grid_report, args.output);
    if (!args.quiet) std::fputs(drawn_line("grid", drawn, args.output).c_str(), stderr);
  } else if (fs::is_directory(args.input)) {
    return run_folder(args, options);
  } else {
    refuse_writing_over_inputs(
        {InputFile{args.input, fs::path(args.input).filename(), fs::path(args.input).filename()}},
        preview_outputs({args.output}), RunReads{args.allow_outside, {}, {}});
    std::optional<ResultCache> cache;
    if (!args.cache.empty()) cache.emplace(args.cache);
    const CachedPreview done = preview_with_cache(args, options, args.input, args.output, cache ? &*cache : nullptr);
    if (!args.quiet) std::fputs(done.line.c_str(), stderr);
  }
  if (!args.no_gallery) write_gallery_page(args.output, args.quiet);
  return kAllDone;
}

constexpr const char* kPreviewHelp =
    R"(Draw IN twice with a CPU deferred renderer, as its legacy spec-gloss materials (before) and as their
in-process conversion to albedo + metalness (after), and write before.png, after.png, difference.png
(ΔE2000 heat map), sheet.png and report.json (ΔE2000 mean/p95, RMS-dB, G-buffer sizes, times).
Given a folder, it draws every .gltf and .glb under it, -j at a time, each into DIR/<its path without
the extension>, and the gallery page over them all.
Exit codes: 0 done, 1 an input could not be drawn (in a folder: its previews not written, and an earlier run's
removed, so the gallery does not show them), 2 bad usage,
3 the previews of a single input cannot be written.)";

void declare_options(CLI::App& cmd, PreviewArgs& args) {
  cmd.add_option("input", args.input, ".gltf or .glb file, or a folder: every one under it, each into OUT/<its path>");
  cmd.add_option("-o,--output", args.output, "output folder (also gets index.html, the gallery page)")->required();
  cmd.add_option("--size", args.size, "image width and height in pixels")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
  cmd.add_option("--width", args.width, "image width (overrides --size)")->check(CLI::Range(16, 8192));
  cmd.add_option("--height", args.height, "image height (overrides --size)")->check(CLI::Range(16, 8192));
  cmd.add_option("--camera", args.camera, "auto (framed on the scene bounds), gltf (the first glTF camera) or N")
      ->capture_default_str();
  cmd.add_option("--yaw", args.yaw, "automatic camera: degrees about +Y from +Z")->capture_default_str();
  cmd.add_option("--pitch", args.pitch, "automatic camera: degrees above the horizon")
      ->check(CLI::Range(-89.0, 89.0))
      ->capture_default_str();
  cmd.add_option("--fov", args.fov, "automatic camera: vertical field of view, degrees")
      ->check(CLI::Range(5.0, 120.0))
      ->capture_default_str();
  cmd.add_option("--env", args.environment, "environment .hdr or .exr (equirectangular); default: built-in sky")
      ->check(CLI::ExistingFile);
  cmd.add_flag("--no-sun", args.no_sun, "light by the environment only");
  cmd.add_option("--brdf", args.brdf, "specular lobe: ggx (glTF Appendix B) or blinn-phong (normalized, (n+2)/8 form)")
      ->check(CLI::IsMember({"ggx", "blinn-phong"}))
      ->capture_default_str();
  cmd.add_option("--legacy-reading", args.legacy_reading,
                 "before side: a = diffuse (1 - max specular) under the dielectric layer's (1 - F), normalised at "
                 "normal incidence; b = weighted by (1 - F) of the specular")
      ->check(CLI::IsMember({"a", "b"}))
      ->capture_default_str();
  cmd.add_option("--tone-map", args.tone_map, "neutral (Khronos PBR Neutral), aces or clamp")
      ->check(CLI::IsMember({"neutral", "aces", "clamp"}))
      ->capture_default_str();
  cmd.add_option("--exposure", args.exposure, "linear exposure scale")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  add_conversion_options(cmd, args.conversion);
  cmd.add_flag("--grid", args.grid, "draw a metalness (rows) x roughness (columns) sphere array instead of IN");
  cmd.add_option("--albedo", args.albedo, "--grid: linear albedo R G B")->expected(3)->check(CLI::Range(0.0, 1.0));
  cmd.add_option("--grid-count", args.grid_count, "--grid: spheres per row and column")
      ->check(CLI::Range(2, 16))
      ->capture_default_str();
  cmd.add_flag("--lint{tolerant}", args.lint,
               "also run the material rules (validate --only materials) on the input and its conversion; their "
               "PBR_* issues go into report.json and the gallery page (--lint=strict for the strict profile)")
      ->check(CLI::IsMember({"tolerant", "strict"}));
  add_batch_options(cmd, "drawn", args.jobs, args.allow_outside);
  cmd.add_flag("--no-gallery", args.no_gallery, "leave DIR/index.html (the page gltf-pbr gallery writes) as it is");
  add_cache_option(cmd, args.cache);
  cmd.add_flag("-q,--quiet", args.quiet, "print nothing on success");
}

}  // namespace

std::function<int()> add_preview_command(CLI::App& app) {
  return add_subcommand<PreviewArgs>(app, "preview", kPreviewHelp, declare_options, run, InputErrors::FailTheInput);
}

}  // namespace gltf_pbr::cli
