// The C++ library's functions (include/gltf_pbr/gltf_pbr.hpp): each maps its options onto the ones
// the tool uses, runs the same code (api/files.hpp, validators/validate.hpp) and hands back the
// report in the tool's JSON formats.
#include <charconv>
#include <cmath>
#include <set>
#include <stdexcept>

#include "api/files.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

// The ranges the tool's option parser enforces: a library caller is refused the same way, by name.
void require(bool in_range, const char* option, const char* range, double value) {
  if (in_range) return;
  char shown[32];  // the shortest text that reads back as the value: 99, 0.1, not 99.000000
  const auto end = std::to_chars(shown, shown + sizeof shown, value).ptr;
  throw std::invalid_argument(std::string(option) + " must be " + range + ", got " + std::string(shown, end));
}
void check(const ConvertFileOptions& o) {
  require(o.png_compression >= 0 && o.png_compression <= 9, "png_compression", "0-9", o.png_compression);
  require(o.jpeg_quality >= 1 && o.jpeg_quality <= 100, "jpeg_quality", "1-100", o.jpeg_quality);
  require(std::isfinite(o.specular_tolerance) && o.specular_tolerance >= 0, "specular_tolerance",
          "a finite number >= 0", o.specular_tolerance);
  require(std::isfinite(o.metalness_tolerance) && o.metalness_tolerance >= 0, "metalness_tolerance",
          "a finite number >= 0", o.metalness_tolerance);
  require(o.preview_size >= 16 && o.preview_size <= 8192, "preview_size", "16-8192", o.preview_size);
}
void check(const PreviewFileOptions& o) {
  require(o.width >= 16 && o.width <= 8192, "width", "16-8192", o.width);
  require(o.height >= 16 && o.height <= 8192, "height", "16-8192", o.height);
  require(o.pitch_degrees >= -89 && o.pitch_degrees <= 89, "pitch_degrees", "-89 to 89", o.pitch_degrees);
  require(o.fov_y_degrees >= 5 && o.fov_y_degrees <= 120, "fov_y_degrees", "5-120", o.fov_y_degrees);
  require(std::isfinite(o.yaw_degrees), "yaw_degrees", "finite", o.yaw_degrees);
}

FileConversion public_result(const FileResult& result) {
  FileConversion out;
  out.input = result.input;
  out.output = result.output;
  out.status = result.status;
  out.error = result.error;
  out.failure = result.failure;
  out.materials = result.report.materials.size();
  for (const MaterialReport& material : result.report.materials) out.texels += material.texels;
  out.total_ms = result.total_ms;
  out.report_json = file_json(result).dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  return out;
}

}  // namespace

FileConversion convert_file(const ConvertJob& job, const ConvertFileOptions& options) {
  check(options);
  return public_result(convert_or_throw(job, options));
}

std::vector<FileConversion> convert_files(std::span<const ConvertJob> jobs, const ConvertFileOptions& options,
                                          unsigned threads, const std::function<void(const FileConversion&)>& on_done) {
  check(options);
  // Two jobs writing one file would race, and the loser's images would stay beside the winner's
  // (the tool refuses the same before a run).
  std::set<fs::path> outputs;
  for (const ConvertJob& job : jobs) {
    std::error_code ec;  // a path that cannot be resolved is compared as written
    fs::path resolved = fs::weakly_canonical(job.output, ec);
    if (ec) resolved = fs::absolute(job.output, ec).lexically_normal();
    if (!outputs.insert(resolved).second)
      throw std::invalid_argument("two jobs write " + job.output.string() + "; give each its own output");
  }
  std::function<void(std::size_t, const FileResult&)> each;
  if (on_done) each = [&](std::size_t, const FileResult& result) { on_done(public_result(result)); };
  const std::vector<FileResult> results = convert_batch(jobs, options, threads, each);
  std::vector<FileConversion> out;
  out.reserve(results.size());
  for (const FileResult& result : results) out.push_back(public_result(result));
  return out;
}

FileValidation validate_file(const fs::path& file, const ValidateFileOptions& options) {
  RuleSet rules = builtin_rules(options.profile);
  IssuePolicy policy;
  if (!options.config.empty()) apply_user_config(options.config, rules, policy);
  ValidateOptions validate;
  if (!options.steps.empty()) {
    validate.steps.clear();
    validate.steps.insert(options.steps.begin(), options.steps.end());
  }
  validate.heatmaps_dir = options.heatmaps_dir;
  validate.allow_outside_uris = options.allow_outside_uris;
  validate.self_intersections = options.self_intersections;
  const Report report = validate_file(file, file.string(), rules, policy, validate);
  FileValidation out;
  out.errors = report.count(Severity::Error);
  out.warnings = report.count(Severity::Warning);
  out.infos = report.count(Severity::Information);
  out.hints = report.count(Severity::Hint);
  out.truncated = report.truncated;
  out.report_json = report_json_text(report);
  out.report_json.pop_back();  // the final newline: the library's JSON texts end at their last brace
  return out;
}

FilePreview preview_file(const fs::path& input, const fs::path& out_dir, const PreviewFileOptions& options) {
  check(options);
  preview::PreviewOptions drawing;
  drawing.width = options.width;
  drawing.height = options.height;
  drawing.gltf_camera = options.gltf_camera;
  drawing.yaw_degrees = options.yaw_degrees;
  drawing.pitch_degrees = options.pitch_degrees;
  drawing.fov_y_degrees = options.fov_y_degrees;
  drawing.environment = options.environment;
  drawing.convert.target = options.target;
  drawing.convert.solver = solver_preset(options.solver, options.error_model);
  const DrawnPreview drawn = preview_one(input, out_dir, drawing, options.allow_outside_uris, options.lint);
  FilePreview out;
  out.flip_mean = drawn.result.metrics.flip_mean;
  out.delta_e_mean = drawn.result.metrics.delta_e_mean;
  out.delta_e_p95 = drawn.result.metrics.delta_e_p95;
  out.rms_db = drawn.result.metrics.rms_db;
  for (const char* image : {"before.png", "after.png", "difference.png", "sheet.png"})
    out.images.push_back(out_dir / image);
  out.report_json = drawn.report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  return out;
}

}  // namespace gltf_pbr
