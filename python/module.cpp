// The Python module `gltf_pbr`: the C++ library (include/gltf_pbr/gltf_pbr.hpp) for Python. Reports
// come back as dicts in the tool's JSON formats, options are keywords spelled as the tool spells
// them, and bad input raises gltf_pbr.InputError carrying the file, the JSON pointer (or byte
// offset) and the reason. The GIL is released while a file is worked on, so Python threads run on.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "gltf_pbr/gltf_pbr.hpp"

namespace py = pybind11;
using namespace py::literals;
namespace fs = std::filesystem;

namespace {

// gltf_pbr.InputError (a ValueError) and gltf_pbr.OutputError (an OSError): strong references held
// for the process's life, so the translator never meets a freed type whatever happens to the module.
PyObject* input_error_type = nullptr;
PyObject* output_error_type = nullptr;

// Text from a file's world (paths, reasons quoting them) as Python decodes file names: bytes that
// are not UTF-8 (Latin-1 names exist) survive as surrogate escapes instead of raising in the
// translator, which would replace the error being raised.
py::str file_text(const std::string& text) {
  return py::reinterpret_steal<py::str>(
      PyUnicode_DecodeFSDefaultAndSize(text.data(), static_cast<Py_ssize_t>(text.size())));
}

py::object from_json(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

template <typename Enum>
Enum parse_choice(const std::string& value, std::optional<Enum> (*parse)(std::string_view), const char* option,
                  const char* choices) {
  if (const std::optional<Enum> parsed = parse(value)) return *parsed;
  throw py::value_error(std::string(option) + " must be one of " + choices + ", got '" + value + "'");
}

gltf_pbr::ErrorModel error_model_of(const std::string& name) {
  return parse_choice(name, gltf_pbr::error_model_from_name, "error_model", "normal-incidence, appearance");
}

gltf_pbr::ConvertFileOptions convert_options(const std::string& target, const std::string& solver,
                                             const std::string& error_model, double specular_tolerance,
                                             int png_compression, int jpeg_quality, double metalness_tolerance,
                                             std::size_t error_samples, bool allow_outside_uris, bool replace_input) {
  gltf_pbr::ConvertFileOptions options;
  options.target = parse_choice(target, gltf_pbr::target_from_name, "target", "metalness, specular");
  options.solver =
      parse_choice(solver, gltf_pbr::solver_effort_from_name, "solver", "fast, balanced, exact, reference");
  options.error_model = error_model_of(error_model);
  options.specular_tolerance = specular_tolerance;
  options.png_compression = png_compression;
  options.jpeg_quality = jpeg_quality;
  options.metalness_tolerance = metalness_tolerance;
  options.error_samples = error_samples;
  options.allow_outside_uris = allow_outside_uris;
  options.replace_input = replace_input;
  return options;
}

// convert's keywords, shared by convert and convert_many; they default as the library's do, as do preview's (below).
const gltf_pbr::ConvertFileOptions kDefaults{};
const gltf_pbr::PreviewFileOptions kPreviewDefaults{};
#define GLTF_PBR_CONVERT_KEYWORDS                                                                                      \
  py::kw_only(), "target"_a = gltf_pbr::target_name(kDefaults.target),                                                 \
                 "solver"_a = gltf_pbr::solver_effort_name(kDefaults.solver),                                          \
                 "error_model"_a = gltf_pbr::error_model_name(kDefaults.error_model),                                  \
                 "specular_tolerance"_a = kDefaults.specular_tolerance,                                                \
                 "png_compression"_a = kDefaults.png_compression, "jpeg_quality"_a = kDefaults.jpeg_quality,           \
                 "metalness_tolerance"_a = kDefaults.metalness_tolerance, "error_samples"_a = kDefaults.error_samples, \
                 "allow_outside_uris"_a = false, "replace_input"_a = false

}  // namespace

PYBIND11_MODULE(gltf_pbr, m) {
  m.doc() =
      "gltf-pbr: converts glTF KHR_materials_pbrSpecularGlossiness materials to metal-rough, validates glTF "
      "files, previews the difference. The same code as the gltf-pbr tool; reports are its JSON formats as dicts.";
  m.attr("__version__") = gltf_pbr::version();

  input_error_type = py::exception<gltf_pbr::InputError>(m, "InputError", PyExc_ValueError).release().ptr();
  output_error_type = py::exception<gltf_pbr::OutputError>(m, "OutputError", PyExc_OSError).release().ptr();
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const gltf_pbr::InputError& e) {
      py::object instance = py::reinterpret_borrow<py::object>(input_error_type)(file_text(e.what()));
      instance.attr("file") = file_text(e.file);
      instance.attr("pointer") = file_text(e.pointer);
      instance.attr("reason") = file_text(e.reason);
      instance.attr("offset") = e.offset ? py::cast(*e.offset) : py::none();
      PyErr_SetObject(input_error_type, instance.ptr());
    } catch (const gltf_pbr::OutputError& e) {
      PyErr_SetObject(output_error_type, file_text(e.what()).ptr());
    }
  });

  m.def(
      "convert",
      [](const fs::path& src, const fs::path& dst, const std::string& target, const std::string& solver,
         const std::string& error_model, double specular_tolerance, int png_compression, int jpeg_quality,
         double metalness_tolerance, std::size_t error_samples, bool allow_outside_uris, bool replace_input,
         const std::optional<fs::path>& preview) {
        const gltf_pbr::ConvertFileOptions options =
            convert_options(target, solver, error_model, specular_tolerance, png_compression, jpeg_quality,
                            metalness_tolerance, error_samples, allow_outside_uris, replace_input);
        gltf_pbr::FileConversion result;
        {
          py::gil_scoped_release released;
          result = gltf_pbr::convert_file({src, dst, preview.value_or(fs::path())}, options);
        }
        return from_json(result.report_json);
      },
      "src"_a, "dst"_a, GLTF_PBR_CONVERT_KEYWORDS, "preview"_a = py::none(),
      "Convert one file's spec-gloss materials; returns its report (per material: outcome, ΔE2000 error, time).\n"
      "Raises InputError for bad input (with .file, .pointer, .offset, .reason), OutputError when dst cannot be "
      "written, RuntimeError when dst is an input (an overwrite refused; replace_input=True allows dst == src), "
      "ValueError for an option out of range. preview: a folder for before/after images.");

  m.def(
      "convert_many",
      [](const std::vector<std::tuple<fs::path, fs::path>>& jobs, unsigned threads, const std::string& target,
         const std::string& solver, const std::string& error_model, double specular_tolerance, int png_compression,
         int jpeg_quality, double metalness_tolerance, std::size_t error_samples, bool allow_outside_uris,
         bool replace_input) {
        const gltf_pbr::ConvertFileOptions options =
            convert_options(target, solver, error_model, specular_tolerance, png_compression, jpeg_quality,
                            metalness_tolerance, error_samples, allow_outside_uris, replace_input);
        std::vector<gltf_pbr::ConvertJob> files;
        for (const auto& [src, dst] : jobs) files.push_back({src, dst, {}});
        std::vector<gltf_pbr::FileConversion> results;
        {
          py::gil_scoped_release released;
          results = gltf_pbr::convert_files(files, options, threads);
        }
        py::list reports;
        for (const gltf_pbr::FileConversion& result : results) reports.append(from_json(result.report_json));
        return reports;
      },
      "jobs"_a, "threads"_a = 0u, GLTF_PBR_CONVERT_KEYWORDS,
      "Convert many (src, dst) pairs on the tool's thread pool, `threads` files at a time (0: one per core). "
      "Returns one report per pair, in order; a file that fails has status 'failed' and an 'error' entry, and "
      "the others go on.");

  m.def(
      "validate",
      [](const fs::path& path, const std::optional<fs::path>& config, const std::string& profile,
         const std::optional<std::vector<std::string>>& only, const std::optional<fs::path>& heatmaps,
         bool allow_outside_uris, bool self_intersections) {
        gltf_pbr::ValidateFileOptions options;
        if (config) options.config = *config;
        options.profile = parse_choice(profile, gltf_pbr::lint_profile_from_name, "profile", "tolerant, strict");
        if (only)
          for (const std::string& step : *only)
            options.steps.push_back(parse_choice(step, gltf_pbr::validation_step_from_name, "only",
                                                 "structure, materials, textures, meshes"));
        if (heatmaps) options.heatmaps_dir = *heatmaps;
        options.allow_outside_uris = allow_outside_uris;
        options.self_intersections = self_intersections;
        gltf_pbr::FileValidation result;
        {
          py::gil_scoped_release released;
          result = gltf_pbr::validate_file(path, options);
        }
        return from_json(result.report_json);
      },
      "path"_a, py::kw_only(), "config"_a = py::none(),
      "profile"_a = gltf_pbr::lint_profile_name(gltf_pbr::ValidateFileOptions{}.profile), "only"_a = py::none(),
      "heatmaps"_a = py::none(), "allow_outside_uris"_a = false, "self_intersections"_a = true,
      "Validate one file; returns the Khronos glTF-Validator's report schema as a dict (issues.messages, "
      "issues.numErrors, ...). Problems in the file are issues, not exceptions; a bad config raises InputError.");

  m.def(
      "preview",
      [](const fs::path& src, const fs::path& out_dir, int size, std::optional<int> width, std::optional<int> height,
         std::optional<int> camera, double yaw, double pitch, double fov, const std::optional<fs::path>& environment,
         const std::string& target, const std::string& solver, const std::string& error_model, bool allow_outside_uris,
         const std::optional<std::string>& lint) {
        gltf_pbr::PreviewFileOptions options;
        options.width = width.value_or(size);
        options.height = height.value_or(size);
        options.gltf_camera = camera.value_or(-1);
        options.yaw_degrees = yaw;
        options.pitch_degrees = pitch;
        options.fov_y_degrees = fov;
        if (environment) options.environment = *environment;
        options.target = parse_choice(target, gltf_pbr::target_from_name, "target", "metalness, specular");
        options.solver =
            parse_choice(solver, gltf_pbr::solver_effort_from_name, "solver", "fast, balanced, exact, reference");
        options.error_model = error_model_of(error_model);
        options.allow_outside_uris = allow_outside_uris;
        if (lint) options.lint = parse_choice(*lint, gltf_pbr::lint_profile_from_name, "lint", "tolerant, strict");
        gltf_pbr::FilePreview result;
        {
          py::gil_scoped_release released;
          result = gltf_pbr::preview_file(src, out_dir, options);
        }
        return from_json(result.report_json);
      },
      "src"_a, "out_dir"_a, py::kw_only(), "size"_a = kPreviewDefaults.width, "width"_a = py::none(),
      "height"_a = py::none(), "camera"_a = py::none(), "yaw"_a = kPreviewDefaults.yaw_degrees,
      "pitch"_a = kPreviewDefaults.pitch_degrees, "fov"_a = kPreviewDefaults.fov_y_degrees,
      "environment"_a = py::none(), "target"_a = gltf_pbr::target_name(kPreviewDefaults.target),
      "solver"_a = gltf_pbr::solver_effort_name(kPreviewDefaults.solver),
      "error_model"_a = gltf_pbr::error_model_name(kPreviewDefaults.error_model), "allow_outside_uris"_a = false,
      "lint"_a = py::none(),
      "Draw src before and after conversion into out_dir (before.png, after.png, difference.png, sheet.png, "
      "report.json); returns report.json as a dict (FLIP, ΔE2000 mean and p95, RMS-dB, times). lint "
      "('tolerant' or 'strict'): also the material rules' PBR_* issues on both sides (material_issues).");
}
