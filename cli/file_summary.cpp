#include "cli/file_summary.hpp"

#include <cstdio>

#include "cli/inputs.hpp"
#include "core/text.hpp"

namespace gltf_pbr::cli {
namespace {

std::string format(const char* pattern, double a, double b, double c) {
  char text[96];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

}  // namespace

std::string file_summary(const FileResult& r, bool verbose) {
  if (r.status == FileStatus::Failed)
    return "FAILED " + printable(r.error ? std::string(r.error->what()) : r.input + ": " + r.failure) + "\n";
  if (r.entry) {  // from the cache or a child process: what its entry says
    const std::size_t materials = r.entry->value("materials", nlohmann::json::array()).size();
    return std::string(r.status == FileStatus::Copied ? "copied " : "converted ") + printable(r.input) + " -> " +
           printable(r.output) + " (" + counted(materials, "material") +
           (r.cached ? ", from the cache)\n" : format(", %.0f ms, in a child process)\n", r.total_ms, 0, 0));
  }
  const ConversionReport& c = r.report;
  // Paths, names, notes and warnings come from the file or the user: printable() escapes them.
  const std::string input = printable(r.input), output = printable(r.output);
  std::string out =
      r.status == FileStatus::Copied
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
