// The conversion report as JSON: one entry per file (`convert --report`, the library's
// FileConversion::report_json, the Python module's dicts) and the run around them.
#include <utility>

#include "api/files.hpp"
#include "core/version.hpp"

namespace gltf_pbr {
namespace {

using nlohmann::json;

json stats_json(const ErrorStats& s) { return {{"mean", s.mean}, {"p95", s.p95}, {"max", s.max}}; }
// null where nothing was measured (a material left as spec-gloss): never a 0 that reads as "exact".
json error_json(const std::optional<ReflectanceError>& e) {
  if (!e) return nullptr;
  return {{"diffuse", stats_json(e->diffuse)},
          {"f0", stats_json(e->f0)},
          {"appearance", e->appearance ? stats_json(*e->appearance) : json(nullptr)}};
}
json times_json(const StageTimes& t) {
  return {{"decode", t.decode_ms}, {"solve", t.solve_ms}, {"encode", t.encode_ms}, {"total", t.total()}};
}

}  // namespace

json file_json(const FileResult& r) {
  if (r.entry) {  // as computed elsewhere, with this run's paths and the time this run took for it
    json out = *r.entry;
    out["input"] = r.input;
    out["output"] = r.output;
    json& times = out["timeMs"];
    // A restored entry's errors describe its output, still true; its times and decodes were the
    // computing run's, and are kept as such: this run decoded nothing for it and timed only the restore.
    if (r.cached && !out.contains("computedTimeMs")) {  // a child's entry has moved them already
      out["computedTimeMs"] = times;
      if (out.contains("imagesDecoded")) out["computedImagesDecoded"] = std::exchange(out["imagesDecoded"], 0);
      if (out.contains("materials") && out["materials"].is_array())
        for (json& material : out["materials"])
          if (material.is_object() && material.contains("timeMs"))
            material["computedTimeMs"] = std::exchange(material["timeMs"], nullptr);
    }
    if (r.cached) {
      out["cached"] = true;
      times = json::object();
    }
    if (!times.is_object()) times = json::object();
    times["total"] = r.total_ms;  // for a child process, its start and exit too
    return out;
  }
  json out = {{"input", r.input}, {"output", r.output}, {"status", file_status_name(r.status)}};
  if (r.error) {
    out["error"] = {{"file", r.error->file}, {"pointer", r.error->pointer}, {"reason", r.error->reason}};
    if (r.error->offset) out["error"]["offset"] = *r.error->offset;
  }
  if (!r.failure.empty()) out["error"] = {{"file", r.input}, {"pointer", ""}, {"reason", r.failure}};
  if (r.status == FileStatus::Failed) {
    out["timeMs"] = {{"total", r.total_ms}};
    return out;
  }
  json materials = json::array();
  for (const MaterialReport& m : r.report.materials) {
    json entry = {{"index", m.index},
                  {"pointer", "/materials/" + std::to_string(m.index)},
                  {"name", m.name},
                  {"outcome", material_outcome_name(m.outcome)},
                  {"texels", m.texels},
                  {"errorSamples", m.error_samples},
                  {"textures",
                   {{"baseColor", texture_outcome_name(m.outputs.base_color)},
                    {"metallicRoughness", texture_outcome_name(m.outputs.metallic_roughness)}}},
                  {"deltaE2000", {{"readingA", error_json(m.error_a)}, {"readingB", error_json(m.error_b)}}},
                  {"timeMs", times_json(m.times)}};
    if (m.metalness_levels)
      entry["metalnessLevels"] = {{"solved", m.metalness_levels->solved}, {"written", m.metalness_levels->written}};
    if (!m.note.empty()) entry["note"] = m.note;
    materials.push_back(entry);
  }
  const ConversionReport& c = r.report;
  out["materials"] = materials;
  out["textures"] = {{"baked", c.textures_baked},         {"reused", c.textures_reused},
                     {"shared", c.textures_shared},       {"texturesRemoved", c.textures_removed},
                     {"imagesRemoved", c.images_removed}, {"samplersRemoved", c.samplers_removed}};
  out["imagesDecoded"] = c.images_decoded;
  json convert_times = times_json(c.times);
  convert_times["total"] = c.wall_ms;  // the stages are summed over materials, some made at once
  out["timeMs"] = {{"load", r.load_ms}, {"convert", convert_times}, {"save", r.save_ms}, {"total", r.total_ms}};
  out["warnings"] = c.warnings;
  return out;
}

json conversion_totals(const json& files) {
  std::size_t converted = 0, copied = 0, failed = 0, materials = 0;
  long long texels = 0;
  double total_ms = 0;
  for (const json& file : files) {
    const std::string status = file.value("status", "");
    converted += status == "converted";
    copied += status == "copied";
    failed += status == "failed";
    if (file.contains("materials")) {
      materials += file["materials"].size();
      for (const json& m : file["materials"]) texels += m.value("texels", 0LL);
    }
    total_ms += file["timeMs"].value("total", 0.0);
  }
  return {{"files", files.size()},  {"converted", converted}, {"copied", copied},  {"failed", failed},
          {"materials", materials}, {"texels", texels},       {"timeMs", total_ms}};
}

json run_json(std::span<const FileResult> results, const ConvertFileOptions& options) {
  const SolverSettings solver = solver_preset(options.solver, options.error_model);
  json files = json::array();
  for (const FileResult& r : results) files.push_back(file_json(r));
  json totals = conversion_totals(files);
  return {{"tool", "gltf-pbr"},
          {"version", tool_version()},
          {"target", target_name(options.target)},
          {"solver",
           {{"name", solver_effort_name(options.solver)},
            {"gridSteps", solver.grid_steps},
            {"refineIterations", solver.refine_iterations},
            {"errorModel", error_model_name(options.error_model)}}},
          {"errorModel",
           "CIEDE2000 between legacy and converted materials per texel (linear sRGB, D65). diffuse, f0: the "
           "reflectance at normal incidence, diffuse weight and F0. Legacy reading A: c_diff = "
           "diffuse*(1-max(specular)); reading B also weights by (1-specular). Core: diffuse = base*(1-m)*0.96, "
           "F0 = mix(0.04, base, m) (glTF 2.0 Appendix B). appearance: the radiance seen at four view angles (n.v = sqrt((k+0.5)/4), equal shares of a sphere's projected area), "
           "diffuse and specular lobes by the split sum (GGX, height-correlated Smith) under the built-in sky's "
           "balance of diffuse light to mirrored radiance (1.94), the legacy diffuse under the dielectric "
           "layer's (1-F) normalised to reading A; the mean over the four angles."},
          {"files", std::move(files)},
          {"totals", std::move(totals)}};
}

}  // namespace gltf_pbr
