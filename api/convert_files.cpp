// Converting files: one at a time as the library's convert_file, many on the pool as the tool's
// `convert` and the library's convert_files.
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <sstream>
#include <system_error>
#include <thread>

#include "api/files.hpp"
#include "api/result_cache.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "core/image.hpp"
#include "core/parallel.hpp"
#include "core/resources.hpp"
#include "core/version.hpp"
#include "rules/rule_set.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

// The input file's bytes for the whole conversion: mapped, or read when it cannot be mapped;
// neither when it cannot be read (the loader then says why).
struct InputFile {
  explicit InputFile(const fs::path& path) : mapped(MappedFile::open(path)) {
    if (!mapped) read = read_file(path);
    if (mapped || read) ++work_counters().documents_read;
  }
  std::optional<std::span<const std::uint8_t>> bytes() const {
    if (mapped) return mapped->bytes();
    if (read) return std::span<const std::uint8_t>(*read);
    return std::nullopt;
  }
  std::optional<MappedFile> mapped;
  std::optional<Bytes> read;
};

// Loads the file from its bytes, parsing its JSON once: the structure step's scan for values that
// loading would drop or misread keeps its tree for the loader. Such a value refuses the file,
// never written back as less than was read. The loader's own errors come first (they name the
// byte), and so does anything that stops the scan itself (memory), rethrown after the load.
Asset load_refusing_value_errors(const fs::path& input, const InputFile& file, bool allow_outside_uris) {
  static const RuleSet rules = builtin_rules();
  const auto resources = std::make_shared<FileResources>(input.parent_path(), allow_outside_uris);
  std::optional<Issue> value_error;
  std::exception_ptr scan_failure;
  if (const auto bytes = file.bytes()) {
    try {
      value_error = first_value_error(input, *bytes, rules, resources);
    } catch (...) {
      scan_failure = std::current_exception();
    }
  }
  Asset asset = load_asset(input, {allow_outside_uris, resources, file.bytes()});
  if (scan_failure) std::rethrow_exception(scan_failure);
  if (value_error) {
    const std::string reason =
        value_error->code + ": " + value_error->message + " (converting would lose or change this value)";
    if (value_error->offset) throw InputError(input.string(), ByteOffset{*value_error->offset}, reason);
    throw InputError(input.string(), value_error->pointer, reason);
  }
  return asset;
}

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code error;
  return a == b || fs::equivalent(a, b, error);
}

using Clock = std::chrono::steady_clock;
double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// For the tests of --isolate only: GLTF_PBR_TEST_FAULT="crash=NAME,hang=NAME,oom=NAME" makes the
// conversion of a file named NAME crash, hang, or allocate without end. Unset, it costs one getenv.
void inject_test_fault(const fs::path& input) {
  const char* faults = std::getenv("GLTF_PBR_TEST_FAULT");
  if (!faults) return;
  const std::string name = input.filename().string();
  std::string_view list = faults;
  while (!list.empty()) {
    const std::string_view fault = list.substr(0, list.find(','));
    list.remove_prefix(std::min(list.size(), fault.size() + 1));
    const std::size_t equals = fault.find('=');
    if (equals == std::string_view::npos || fault.substr(equals + 1) != name) continue;
    const std::string_view kind = fault.substr(0, equals);
    if (kind == "crash") std::abort();  // SIGABRT: the sanitizers turn a SIGSEGV into an exit code
    if (kind == "hang")
      for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
    if (kind == "oom")
      for (std::vector<std::unique_ptr<char[]>> blocks;;) {  // touched, so it is resident
        blocks.emplace_back(new char[64 << 20]);
        std::memset(blocks.back().get(), 1, 64 << 20);
      }
  }
}

// A job's result before anything happened to it: failed until something succeeds.
FileResult result_of(const ConvertJob& job) {
  FileResult result;
  result.input = job.input.string();
  result.output = job.output.string();
  return result;
}

fs::path folder_of(const fs::path& file) { return file.parent_path().empty() ? fs::path(".") : file.parent_path(); }

// What every conversion of a run depends on besides its files (ResultCache::key): the options that
// change an output or its report entry, the image limit, the rules and the tool's version.
std::string run_settings(const ConvertFileOptions& options) {
  std::ostringstream text;
  text.precision(17);
  text << "convert " << tool_version() << " target " << target_name(options.target) << " solver "
       << solver_effort_name(options.solver) << " error-model " << error_model_name(options.error_model)
       << " specular-tolerance " << options.specular_tolerance << " png-libdeflate " << options.png_compression
       << " jpeg " << options.jpeg_quality << " metalness-tolerance " << options.metalness_tolerance
       << " error-samples " << options.error_samples << " allow-outside " << options.allow_outside_uris
       << " max-image-pixels " << max_image_pixels() << " preview-size " << options.preview_size << " preview-lint "
       << (options.preview_lint ? lint_profile_name(*options.preview_lint) : "off") << '\n'
       << builtin_rules_text();
  return text.str();
}

// And what one job adds: the names its outputs take come from the output's file name, and its
// resources are copied only when it goes to another folder than its input.
std::string job_settings(const std::string& run, const ConvertJob& job) {
  std::error_code error;
  const bool same_folder = fs::equivalent(folder_of(job.input), folder_of(job.output), error);
  return run + "\noutput " + job.output.filename().string() + " input " + job.input.extension().string() +
         (same_folder ? " beside its input" : " elsewhere") + (job.preview_dir.empty() ? "" : " with preview");
}

// A job restored from the cache when it holds the result, else converted and stored.
FileResult convert_cached(const ConvertJob& job, const ConvertFileOptions& options, const std::string& run,
                          ResultCache& cache) {
  const auto start = Clock::now();
  const std::optional<std::string> key =
      cache.key(job.input, job_settings(run, job), options.allow_outside_uris, folder_of(job.output));
  const fs::path roots[] = {folder_of(job.output), job.preview_dir};
  // Only what store() below keeps: an entry of a file converted or copied.
  const auto stored_here = [](const nlohmann::json& entry) {
    const auto status = entry.is_object() && entry.contains("status") && entry["status"].is_string()
                            ? file_status_from_name(entry["status"].get<std::string>())
                            : std::nullopt;
    return status == FileStatus::Converted || status == FileStatus::Copied;
  };
  if (key) {
    try {
      if (std::optional<nlohmann::json> entry = cache.restore(*key, roots, stored_here)) {
        FileResult hit = result_of(job);
        hit.status = *file_status_from_name((*entry)["status"].get<std::string>());
        hit.entry = std::move(*entry);
        hit.cached = true;
        hit.total_ms = ms_between(start, Clock::now());
        return hit;
      }
    } catch (const OutputError& e) {
      cache.leave_out(*key);
      FileResult failed = result_of(job);
      failed.failure = "output " + job.output.string() + ": " + e.what();
      failed.total_ms = ms_between(start, Clock::now());
      return failed;
    }
  }
  FileResult result = convert_one(job, options);
  // A preview drawn without a texture it could not decode (memory, a damaged file) is not kept.
  if (key && result.status != FileStatus::Failed && result.preview_complete) {
    const ResultCache::Outputs outputs[] = {{roots[0], result.written}, {roots[1], result.preview_written}};
    cache.store(*key, file_json(result), outputs);
  } else if (key) {
    cache.leave_out(*key);
  }
  return result;
}

}  // namespace

// The library converts as the tool does when left to its defaults (the solver's effort is a
// preset, solver_preset, not a default of SolverSettings).
static_assert(ConvertFileOptions{}.target == ConvertOptions{}.target &&
              ConvertFileOptions{}.error_model == ConvertOptions{}.solver.error_model &&
              ConvertFileOptions{}.specular_tolerance == ConvertOptions{}.specular_tolerance &&
              ConvertFileOptions{}.png_compression == ConvertOptions{}.png_compression &&
              ConvertFileOptions{}.jpeg_quality == ConvertOptions{}.jpeg_quality &&
              ConvertFileOptions{}.metalness_tolerance == ConvertOptions{}.metalness_tolerance &&
              ConvertFileOptions{}.error_samples == ConvertOptions{}.max_error_samples);

ConvertOptions conversion_options(const ConvertFileOptions& options) {
  ConvertOptions converter;
  converter.target = options.target;
  converter.solver = solver_preset(options.solver, options.error_model);
  converter.specular_tolerance = options.specular_tolerance;
  converter.png_compression = options.png_compression;
  converter.jpeg_quality = options.jpeg_quality;
  converter.metalness_tolerance = options.metalness_tolerance;
  converter.max_error_samples = options.error_samples;
  return converter;
}

FileResult convert_or_throw(const ConvertJob& job, const ConvertFileOptions& options) {
  inject_test_fault(job.input);
  FileResult result = result_of(job);
  ConvertOptions converter = conversion_options(options);
  DecodedImages decoded;  // under --preview, the conversion's pixels: the preview decodes none of them again
  if (!job.preview_dir.empty()) converter.keep_decoded = &decoded;
  const auto start = Clock::now();
  const InputFile input(job.input);  // read once: loaded, and copied as it is when nothing changes
  Asset asset = load_refusing_value_errors(job.input, input, options.allow_outside_uris);
  if (input.mapped) input.mapped->release_pages();  // a copy made below maps them again from the page cache
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
    result.written = copy_asset_verbatim(asset, job.output, input.bytes());
    result.status = FileStatus::Copied;
  } else {
    result.written = save_asset(asset, job.output, /*replace_input=*/in_place);
    result.status = FileStatus::Converted;
  }
  result.save_ms = ms_between(converted, Clock::now());
  if (original) {
    // The material rules read the conversion's pixels before the scene takes and frees them.
    nlohmann::json issues = material_issues(*original, asset, options.preview_lint, &decoded);
    preview::PreviewOptions preview_options;
    preview_options.convert = converter;
    preview_options.width = preview_options.height = options.preview_size;
    preview::PreviewResult drawn = preview::render_pair(*original, asset, preview_options, &decoded);
    drawn.conversion = result.report;  // the report names each material's outcome, error and time
    result.preview_complete = drawn.scene.warnings.empty();  // an empty scene's preview is complete
    if (drew_nothing(drawn)) drawn.scene.warnings.push_back(kNothingToDraw);
    nlohmann::json report = preview::preview_report(drawn, preview_options);
    report["input"] = job.input.string();
    report["material_issues"] = std::move(issues);
    result.preview_written = preview::write_preview(drawn, report, job.preview_dir);
  }
  result.total_ms = ms_between(start, Clock::now());
  return result;
}

FileResult convert_one(const ConvertJob& job, const ConvertFileOptions& options) {
  const auto start = Clock::now();
  try {
    return convert_or_throw(job, options);
  } catch (const InputError& e) {
    FileResult failed = result_of(job);
    failed.error = e;
    failed.total_ms = ms_between(start, Clock::now());
    return failed;
  } catch (const std::exception& e) {
    std::string reason = e.what();
    if (dynamic_cast<const OutputError*>(&e))  // names the output it was writing, then the file and errno's text
      reason = "output " + job.output.string() + ": " + reason;
    else if (dynamic_cast<const std::bad_alloc*>(&e))
      reason = "out of memory while converting (--max-image-pixels lowers the largest image accepted)";
    FileResult failed = result_of(job);
    failed.failure = reason;
    failed.total_ms = ms_between(start, Clock::now());
    return failed;
  }
}

std::vector<FileResult> convert_batch(std::span<const ConvertJob> jobs, const ConvertFileOptions& options,
                                      unsigned threads,
                                      const std::function<void(std::size_t, const FileResult&)>& on_done,
                                      ResultCache* cache, const ConvertJobFunction& convert_job) {
  std::vector<FileResult> results(jobs.size());
  const std::int64_t at_once = threads ? threads : hardware_threads();
  const std::string run = cache ? run_settings(options) : "";
  ThreadPool::shared().run(
      static_cast<std::int64_t>(jobs.size()),
      [&](std::int64_t index) {
        const auto i = static_cast<std::size_t>(index);
        results[i] = convert_job ? convert_job(i, jobs[i])
                     : cache     ? convert_cached(jobs[i], options, run, *cache)
                                 : convert_one(jobs[i], options);
        if (on_done) on_done(i, results[i]);
      },
      at_once);
  return results;
}

}  // namespace gltf_pbr
