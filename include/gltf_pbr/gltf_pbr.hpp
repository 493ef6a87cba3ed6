// gltf-pbr as a library: what the `gltf-pbr` tool does to a file, called from a program. Link
// gltf_pbr::gltf_pbr (find_package(gltf_pbr CONFIG REQUIRED)); the Python module `gltf_pbr` wraps
// these same functions. The tool, this library and the module run one implementation (api/).
//
// Every report comes as JSON text in the tool's own formats (README: Convert, Validate, Preview):
// a file's entry of `convert --report`, the Khronos validator's report schema, `preview`'s
// report.json. Inputs are never overwritten unless asked, outputs are written atomically, and no
// file outside an asset's folder is opened unless allow_outside_uris is set.
//
// Thread safety: every function may be called from several threads at once. Batches and the work
// inside one file run on the process's one thread pool (hardware threads - 1 workers).
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gltf_pbr/error.hpp"
#include "gltf_pbr/export.hpp"

namespace gltf_pbr {

// The library's version, the one the tool's --version and every report give ("0.1.0").
GLTF_PBR_API std::string version();

// How hard the material rules (PBR_*) judge, as Filament's material guide keeps a strict and a
// tolerant range (rules/materials.json holds both): Tolerant warns where a value is clearly wrong for
// what renders (a reference-quality asset passes), Strict where it leaves the calibrated ranges.
// Used by validate and by the previews' --lint.
enum class LintProfile { Tolerant, Strict };
GLTF_PBR_API std::optional<LintProfile> lint_profile_from_name(std::string_view name);  // "tolerant", "strict"
GLTF_PBR_API const char* lint_profile_name(LintProfile profile);

// ---- convert: KHR_materials_pbrSpecularGlossiness materials to core metal-rough ----

enum class Target {
  Metalness,  // core glTF only
  Specular,   // + KHR_materials_specular / KHR_materials_ior where the metalness fit misses
};

// Metalness search effort: error against run time. Reference: the archived extension's brightness
// formula, for comparison only.
enum class SolverEffort { Fast, Balanced, Exact, Reference };

// What the solve matches (converter/solver.hpp): the reflectance at normal incidence (diffuse
// weight and F0; the default), or, with that fit's metalness, a base colour that matches it and
// the look over view angles (both lobes together) half and half. The second draws rounded shapes
// closer in the preview under every environment measured, but flat glossy ones closer or farther
// by the environment, and VC farther under the built-in sky: so it is not the default
// (bench/RESULTS.md, sessions 41 and 42).
enum class ErrorModel { NormalIncidence, Appearance };

// The names the tool's options and the Python module use ("metalness", "specular"; "fast",
// "balanced", "exact", "reference"); std::nullopt for any other.
GLTF_PBR_API std::optional<Target> target_from_name(std::string_view name);
GLTF_PBR_API std::optional<SolverEffort> solver_effort_from_name(std::string_view name);
GLTF_PBR_API const char* target_name(Target target);
GLTF_PBR_API const char* solver_effort_name(SolverEffort effort);
GLTF_PBR_API std::optional<ErrorModel> error_model_from_name(
    std::string_view name);  // "appearance", "normal-incidence"
GLTF_PBR_API const char* error_model_name(ErrorModel model);

struct ConvertFileOptions {
  Target target = Target::Metalness;
  SolverEffort solver = SolverEffort::Balanced;
  ErrorModel error_model = ErrorModel::NormalIncidence;
  double specular_tolerance = 2.0;       // ΔE2000 (p95) a metalness fit may miss by (Target::Specular)
  int png_compression = 1;  // deflate level 0-9 of baked PNG textures (libdeflate; 9 is smallest; images of at most 64
                            // KiB of rows always take 9)
  int jpeg_quality = 90;                 // 1-100, of base colours baked from JPEG diffuse textures
  // ΔE2000 a material's error (the sum of its diffuse and F0 means) may rise by where its metalness
  // map is written with fewer distinct values (the fewest of 2 to 16 levels: smaller files); 0
  // writes every value the solve gave.
  double metalness_tolerance = 0.002;
  std::size_t error_samples = 1u << 16;  // texels sampled per texture for the error statistics (0: all)
  bool allow_outside_uris = false;       // read absolute or "../" resource URIs
  bool replace_input = false;            // output == input replaces it (atomically); else refused
  int preview_size = 512;                // width and height of a ConvertJob's preview images
  // Also run the material rules (PBR_*) on a ConvertJob's input and output, into its preview's
  // report.json ("material_issues") and the gallery page; std::nullopt: not run (null there).
  std::optional<LintProfile> preview_lint;
};

struct ConvertJob {
  ConvertJob(std::filesystem::path input_, std::filesystem::path output_, std::filesystem::path preview_dir_ = {})
      : input(std::move(input_)), output(std::move(output_)), preview_dir(std::move(preview_dir_)) {}
  std::filesystem::path input, output;
  std::filesystem::path preview_dir;  // not empty: also draw before and after into this folder
};

enum class FileStatus {
  Converted,  // written with its materials converted
  Copied,     // nothing to convert: the input's bytes written as they were
  Failed,     // see error or failure; nothing was written
};
GLTF_PBR_API const char* file_status_name(FileStatus status);  // "converted", "copied", "failed"

struct FileConversion {
  std::filesystem::path input, output;
  FileStatus status = FileStatus::Failed;
  std::optional<InputError> error;  // Failed on bad input: the file, JSON pointer or byte, reason
  std::string failure;              // Failed for another reason (an output not writable, no memory)
  std::size_t materials = 0;        // spec-gloss materials found
  long long texels = 0;             // texels solved
  double total_ms = 0;
  // This file's entry of `gltf-pbr convert --report`: per material the outcome, the ΔE2000 error
  // (null where not measured) and the time it cost; textures written, reused and removed.
  std::string report_json;
};

// Converts one file: convert_file({"in.gltf", "out.glb"}). Throws InputError for bad input, OutputError or
// std::runtime_error when the output cannot be written, std::invalid_argument for an option out of its range; on
// success status is Converted or Copied.
GLTF_PBR_API FileConversion convert_file(const ConvertJob& job, const ConvertFileOptions& options = {});

// Converts many files on the process's pool, at most `threads` at a time (0: one per hardware
// thread). A file that fails is reported as Failed and the others go on; results keep the jobs'
// order. on_done, if given, is called once per file as it finishes, from the thread that ran it.
// Throws std::invalid_argument, before any file is written, for an option out of its range or two
// jobs that write one output.
GLTF_PBR_API std::vector<FileConversion> convert_files(std::span<const ConvertJob> jobs,
                                                       const ConvertFileOptions& options = {}, unsigned threads = 0,
                                                       const std::function<void(const FileConversion&)>& on_done = {});

// ---- validate: structure, material plausibility, textures and meshes ----

enum class ValidationStep { Structure, Materials, Textures, Meshes };
// "structure", "materials", "textures", "meshes", as the tool's --only spells them.
GLTF_PBR_API std::optional<ValidationStep> validation_step_from_name(std::string_view name);
GLTF_PBR_API const char* validation_step_name(ValidationStep step);

struct ValidateFileOptions {
  std::vector<ValidationStep> steps;            // empty: all four
  LintProfile profile = LintProfile::Tolerant;  // a config's thresholds apply on top of it
  // The Khronos validator's config shape, YAML or JSON (max-issues, ignore, only, override) plus
  // our thresholds; empty: the built-in rules.
  std::filesystem::path config;
  std::filesystem::path heatmaps_dir;  // not empty: a PNG per failing texture showing where it fails
  bool allow_outside_uris = false;
  bool self_intersections = true;  // the costliest mesh check
};

struct FileValidation {
  std::size_t errors = 0, warnings = 0, infos = 0, hints = 0;
  bool truncated = false;   // stopped at the config's max-issues
  std::string report_json;  // the Khronos validator's report schema (validatorVersion: ours)
};

// Validates one file. Bad input never throws: it becomes issues in the report. Throws InputError
// for an unreadable or invalid config file.
GLTF_PBR_API FileValidation validate_file(const std::filesystem::path& file, const ValidateFileOptions& options = {});

// ---- preview: the asset drawn before and after conversion, and the difference measured ----

struct PreviewFileOptions {
  int width = 512, height = 512;
  int gltf_camera = -1;  // >= 0: through the asset's N-th perspective camera; else framed automatically
  double yaw_degrees = 35, pitch_degrees = 20, fov_y_degrees = 40;  // the automatic framing
  std::filesystem::path environment;                                // .hdr / .exr; empty: the built-in procedural sky
  Target target = Target::Metalness;
  SolverEffort solver = SolverEffort::Balanced;
  ErrorModel error_model = ErrorModel::NormalIncidence;
  bool allow_outside_uris = false;
  // Also run the material rules (PBR_*) on the input and its conversion, into report.json's
  // "material_issues"; std::nullopt: not run (null there).
  std::optional<LintProfile> lint;
};

struct FilePreview {
  double flip_mean = 0, delta_e_mean = 0, delta_e_p95 = 0, rms_db = 0;
  std::vector<std::filesystem::path> images;  // before, after, difference and sheet PNGs written
  std::string report_json;                    // report.json, also written into the folder
};

// Draws `input` as its legacy spec-gloss materials and as their conversion, and writes
// before.png, after.png, difference.png, sheet.png and report.json into out_dir atomically.
// Throws InputError for bad input or a scene with nothing visible to draw, std::invalid_argument
// for an option out of its range.
GLTF_PBR_API FilePreview preview_file(const std::filesystem::path& input, const std::filesystem::path& out_dir,
                                      const PreviewFileOptions& options = {});

}  // namespace gltf_pbr
