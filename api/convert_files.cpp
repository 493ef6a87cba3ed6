// Converting files: one at a time as the library's convert_file, many on the pool as the tool's
// `convert` and the library's convert_files.
#include <chrono>
#include <system_error>

#include "api/files.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

// A value loading would drop or misread is refused, never written back as less than was read.
void refuse_value_errors(const fs::path& input) {
  static const RuleSet rules = builtin_rules();
  if (const std::optional<Issue> issue = first_value_error(input, rules)) {
    const std::string reason = issue->code + ": " + issue->message + " (converting would lose or change this value)";
    if (issue->offset) throw InputError(input.string(), ByteOffset{*issue->offset}, reason);
    throw InputError(input.string(), issue->pointer, reason);
  }
}

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code error;
  return a == b || fs::equivalent(a, b, error);
}

using Clock = std::chrono::steady_clock;
double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

ConvertOptions conversion_options(const ConvertFileOptions& options) {
  ConvertOptions converter;
  converter.target = options.target;
  converter.solver = solver_preset(options.solver);
  converter.specular_tolerance = options.specular_tolerance;
  converter.png_compression = options.png_compression;
  converter.jpeg_quality = options.jpeg_quality;
  converter.max_error_samples = options.error_samples;
  return converter;
}

FileResult convert_or_throw(const ConvertJob& job, const ConvertFileOptions& options) {
  FileResult result{job.input.string(), job.output.string(), FileStatus::Failed, std::nullopt, "", {}, 0, 0, 0};
  const ConvertOptions converter = conversion_options(options);
  const auto start = Clock::now();
  Asset asset = load_asset(job.input, {options.allow_outside_uris});  // its own errors first: they name the byte
  refuse_value_errors(job.input);
  const auto loaded = Clock::now();
  result.load_ms = ms_between(start, loaded);
  // The preview draws the legacy asset beside its conversion: keep the original only then.
  const std::optional<Asset> original = job.preview_dir.empty() ? std::nullopt : std::optional<Asset>(asset);
  result.report = convert(asset, converter);
  const auto converted = Clock::now();
  const bool in_place = options.replace_input && same_file(job.input, job.output);
  const bool same_format = asset.binary == (job.output.extension() == ".glb");
  if (!result.report.changed() && in_place) {
    result.status = FileStatus::Copied;  // nothing to write: the input already is the result
  } else if (!result.report.changed() && same_format) {
    copy_asset_verbatim(asset, job.output);
    result.status = FileStatus::Copied;
  } else {
    save_asset(asset, job.output, /*replace_input=*/in_place);
    result.status = FileStatus::Converted;
  }
  result.save_ms = ms_between(converted, Clock::now());
  if (original) {
    preview::PreviewOptions preview_options;
    preview_options.convert = converter;
    const preview::PreviewResult drawn = preview::render_pair(*original, asset, preview_options);
    preview::write_preview(drawn, preview::preview_report(drawn, preview_options), job.preview_dir);
  }
  result.total_ms = ms_between(start, Clock::now());
  return result;
}

FileResult convert_one(const ConvertJob& job, const ConvertFileOptions& options) {
  const auto start = Clock::now();
  try {
    return convert_or_throw(job, options);
  } catch (const InputError& e) {
    FileResult failed{job.input.string(), job.output.string(), FileStatus::Failed, e, "", {}, 0, 0, 0};
    failed.total_ms = ms_between(start, Clock::now());
    return failed;
  } catch (const std::exception& e) {
    std::string reason = e.what();
    if (dynamic_cast<const OutputError*>(&e))  // names the output it was writing, then the file and errno's text
      reason = "output " + job.output.string() + ": " + reason;
    else if (dynamic_cast<const std::bad_alloc*>(&e))
      reason = "out of memory while converting (--max-image-pixels lowers the largest image accepted)";
    FileResult failed{job.input.string(), job.output.string(), FileStatus::Failed, std::nullopt, reason, {}, 0, 0, 0};
    failed.total_ms = ms_between(start, Clock::now());
    return failed;
  }
}

std::vector<FileResult> convert_batch(std::span<const ConvertJob> jobs, const ConvertFileOptions& options,
                                      unsigned threads,
                                      const std::function<void(std::size_t, const FileResult&)>& on_done) {
  std::vector<FileResult> results(jobs.size());
  const std::int64_t at_once = threads ? threads : hardware_threads();
  ThreadPool::shared().run(
      static_cast<std::int64_t>(jobs.size()),
      [&](std::int64_t index) {
        const auto i = static_cast<std::size_t>(index);
        results[i] = convert_one(jobs[i], options);
        if (on_done) on_done(i, results[i]);
      },
      at_once);
  return results;
}

}  // namespace gltf_pbr
