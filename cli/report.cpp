#include "cli/report.hpp"

#include <cstdio>

#include "cli/inputs.hpp"
#include "core/text.hpp"
#include "core/version.hpp"

namespace gltf_pbr::cli {
namespace {

using nlohmann::json;

json stats_json(const ErrorStats& s) { return {{"mean", s.mean}, {"p95", s.p95}, {"max", s.max}}; }
// null where nothing was measured (a material left as spec-gloss): never a 0 that reads as "exact".
json error_json(const std::optional<ReflectanceError>& e) {
  if (!e) return nullptr;
  return {{"diffuse", stats_json(e->diffuse)}, {"f0", stats_json(e->f0)}};
}
json times_json(const StageTimes& t) {
  return {{"decode", t.decode_ms}, {"solve", t.solve_ms}, {"encode", t.encode_ms}, {"total", t.total()}};
}

std::string format(const char* pattern, double a, double b, double c) {
  char text[96];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

}  // namespace

json file_json(const FileResult& r) {
  json out = {{"input", r.input}, {"output", r.output}, {"status", r.status}};
  if (r.error) {
    out["error"] = {{"file", r.error->file}, {"pointer", r.error->pointer}, {"reason", r.error->reason}};
    if (r.error->offset) out["error"]["offset"] = *r.error->offset;
  }
  if (!r.failure.empty()) out["error"] = {{"file", r.input}, {"pointer", ""}, {"reason", r.failure}};
  if (r.status == "failed") return out;
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
    if (!m.note.empty()) entry["note"] = m.note;
    materials.push_back(entry);
  }
  const ConversionReport& c = r.report;
  out["materials"] = materials;
  out["textures"] = {{"baked", c.textures_baked},         {"reused", c.textures_reused},
                     {"shared", c.textures_shared},       {"texturesRemoved", c.textures_removed},
                     {"imagesRemoved", c.images_removed}, {"samplersRemoved", c.samplers_removed}};
  out["imagesDecoded"] = c.images_decoded;
  out["timeMs"] = {{"load", r.load_ms}, {"convert", times_json(c.times)}, {"save", r.save_ms}, {"total", r.total_ms}};
  out["warnings"] = c.warnings;
  return out;
}

json run_json(const std::vector<FileResult>& results, const ConvertOptions& options, const std::string& solver_name) {
  json files = json::array();
  int converted = 0, copied = 0, failed = 0;
  long long materials = 0, texels = 0;
  double total_ms = 0;
  for (const FileResult& r : results) {
    files.push_back(file_json(r));
    converted += r.status == "converted";
    copied += r.status == "copied";
    failed += r.status == "failed";
    materials += static_cast<long long>(r.report.materials.size());
    for (const auto& m : r.report.materials) texels += m.texels;
    total_ms += r.total_ms;
  }
  return {{"tool", "gltf-pbr"},
          {"version", tool_version()},
          {"target", options.target == Target::Metalness ? "metalness" : "specular"},
          {"solver",
           {{"name", solver_name},
            {"gridSteps", options.solver.grid_steps},
            {"refineIterations", options.solver.refine_iterations}}},
          {"errorModel",
           "CIEDE2000 between legacy and converted reflectance at normal incidence, per texel (linear sRGB, D65): "
           "diffuse weight and F0. Legacy reading A: c_diff = diffuse*(1-max(specular)); reading B also weights "
           "by (1-specular). Core: diffuse = base*(1-m)*0.96, F0 = mix(0.04, base, m) (glTF 2.0 Appendix B)."},
          {"files", files},
          {"totals",
           {{"files", results.size()},
            {"converted", converted},
            {"copied", copied},
            {"failed", failed},
            {"materials", materials},
            {"texels", texels},
            {"timeMs", total_ms}}}};
}

std::string file_summary(const FileResult& r, bool verbose) {
  if (r.status == "failed")
    return "FAILED " + printable(r.error ? std::string(r.error->what()) : r.input + ": " + r.failure) + "\n";
  const ConversionReport& c = r.report;
  // Paths, names, notes and warnings come from the file or the user: printable() escapes them.
  const std::string input = printable(r.input), output = printable(r.output);
  std::string out =
      r.status == "copied"
          ? "copied " + input + " -> " + output + " (nothing to convert)\n"
          : "converted " + input + " -> " + output + " (" + counted(c.materials.size(), "material") +
                format(", %.0f ms, %.0f images decoded)\n", r.total_ms, static_cast<double>(c.images_decoded), 0);
  double worst = 0;
  for (const MaterialReport& m : c.materials) {
    if (m.error_a) worst = std::max(worst, m.error_a->worst());
    if (!verbose && m.outcome == MaterialOutcome::Metalness) continue;
    const std::string error =
        m.error_a ? format(", ΔE2000 diffuse mean %.2f max %.2f", m.error_a->diffuse.mean, m.error_a->diffuse.max, 0) +
                        format(", F0 mean %.2f max %.2f", m.error_a->f0.mean, m.error_a->f0.max, 0)
                  : ", ΔE2000 not measured";
    out += "  /materials/" + std::to_string(m.index) + " " + (m.name.empty() ? "" : "'" + printable(m.name) + "' ") +
           material_outcome_name(m.outcome) + format(": texels %.0f", static_cast<double>(m.texels), 0, 0) + error +
           format(", %.1f ms", m.times.total(), 0, 0) + (m.note.empty() ? "" : " (" + printable(m.note) + ")") + "\n";
  }
  if (!c.materials.empty()) out += format("  worst material ΔE2000 (reading A): %.2f\n", worst, 0, 0);
  for (const std::string& w : c.warnings) out += "  warning: " + printable(w) + "\n";
  return out;
}

}  // namespace gltf_pbr::cli
