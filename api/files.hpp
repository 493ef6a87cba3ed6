// The file-level operations every front end runs: the tool (cli/), the C++ library
// (include/gltf_pbr/gltf_pbr.hpp, api/library.cpp) and the Python module (python/). One file in,
// its outputs written atomically, a result that says what happened; batches on the one pool.
#pragma once
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "converter/convert.hpp"
#include "gltf_pbr/gltf_pbr.hpp"
#include "preview/preview.hpp"

namespace gltf_pbr {

// One file's conversion, with the typed report the tool prints for people.
struct FileResult {
  std::string input, output;
  FileStatus status = FileStatus::Failed;
  std::optional<InputError> error;  // Failed on bad input
  std::string failure;              // Failed for another reason
  ConversionReport report;
  double load_ms = 0, save_ms = 0, total_ms = 0;
  std::vector<fs::path> written, preview_written;  // the files this run wrote: outputs, preview
  bool preview_complete = true;                    // no texture left out of the preview
  // The report entry as JSON when it was not computed here: restored by --cache (`cached`), or
  // written by the child process that converted the file (--isolate). `report` is then empty.
  std::optional<nlohmann::json> entry;
  bool cached = false;
};

std::optional<FileStatus> file_status_from_name(std::string_view name);

class ResultCache;

// The converter's options for the file options.
ConvertOptions conversion_options(const ConvertFileOptions& options);

// Loads, refuses values that writing back would lose, converts, writes (or copies the bytes when
// nothing changed) and draws the preview when the job asks for one. Throws what it meets.
FileResult convert_or_throw(const ConvertJob& job, const ConvertFileOptions& options);

// The same, with any failure caught into the result: one bad file never ends a batch.
FileResult convert_one(const ConvertJob& job, const ConvertFileOptions& options);

// convert_one for every job on the process's pool, at most `threads` files at a time (0: one per
// hardware thread); on_done(job index, result) as each finishes, on the thread that ran it. With a
// cache, a job whose result it holds is restored from it, and one computed is stored in it. With
// `convert_job`, each job is converted by it instead of convert_one (and the cache is its own).
using ConvertJobFunction = std::function<FileResult(std::size_t, const ConvertJob&)>;
std::vector<FileResult> convert_batch(std::span<const ConvertJob> jobs, const ConvertFileOptions& options,
                                      unsigned threads,
                                      const std::function<void(std::size_t, const FileResult&)>& on_done,
                                      ResultCache* cache = nullptr, const ConvertJobFunction& convert_job = {});

// A file's entry of `convert --report`, and the whole report around several.
nlohmann::json file_json(const FileResult& result);
nlohmann::json run_json(std::span<const FileResult> results, const ConvertFileOptions& options);
// The report's "totals", counted from its file entries (also for reports merged from shards).
nlohmann::json conversion_totals(const nlohmann::json& files);

// The preview of one file as `gltf-pbr preview` draws it: loaded, converted in memory, drawn both
// ways, compared, and written into out_dir with its report (which names the input). Throws
// InputError for bad input or a scene with nothing visible to draw.
struct DrawnPreview {
  preview::PreviewResult result;
  nlohmann::json report;
  std::vector<fs::path> written;  // the files of out_dir
};
// `lint`: also run the material rules on the input and its conversion (material_issues).
DrawnPreview preview_one(const fs::path& input, const fs::path& out_dir, const preview::PreviewOptions& options,
                         bool allow_outside_uris, std::optional<LintProfile> lint = std::nullopt);

// The PBR_* issues that `validate --only materials --profile P` raises on a preview's input and on
// its conversion, as report.json's "material_issues": {"profile", "before": [...], "after": [...]},
// each issue {code, severity (its name), pointer, message, count when folded}; null when `lint`
// is std::nullopt (not run).
// `decoded`: pixels the run already holds (the conversion's), read instead of decoding again.
nlohmann::json material_issues(const Asset& input, const Asset& converted, std::optional<LintProfile> lint,
                               DecodedImages* decoded = nullptr);

// A picture of nothing compares equal to itself: that is no pass. `preview` refuses one;
// `convert --preview`, whose conversion stands, reports it with null figures and this warning.
inline constexpr const char* kNothingToDraw = "nothing to draw: the scene has no visible triangles";
inline bool drew_nothing(const preview::PreviewResult& result) { return result.metrics.pixels_compared == 0; }

// The tail of preview_one for any drawn result (the tool's --grid too): refuses a picture of
// nothing, adds `extra` and "input": name to the report, and writes the folder.
DrawnPreview finish_preview(preview::PreviewResult result, const preview::PreviewOptions& options,
                            const std::string& name, nlohmann::json extra, const fs::path& out_dir);

}  // namespace gltf_pbr
