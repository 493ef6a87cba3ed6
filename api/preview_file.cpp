// Previewing files: the tool's `preview` and the library's preview_file.
#include <algorithm>

#include "api/files.hpp"
#include "core/error.hpp"

namespace gltf_pbr {

DrawnPreview finish_preview(preview::PreviewResult result, const preview::PreviewOptions& options,
                            const std::string& name, nlohmann::json extra, const fs::path& out_dir) {
  // A picture of nothing compares equal to itself: that is not a pass.
  if (std::none_of(result.covered.begin(), result.covered.end(), [](std::uint8_t c) { return c != 0; }))
    throw InputError(name, "", "nothing to draw: the scene has no visible triangles");
  nlohmann::json report = preview::preview_report(result, options);
  report["input"] = name;
  if (extra.is_object()) report.update(extra);
  std::vector<fs::path> written = preview::write_preview(result, report, out_dir);
  return {std::move(result), std::move(report), std::move(written)};
}

DrawnPreview preview_one(const fs::path& input, const fs::path& out_dir, const preview::PreviewOptions& options,
                         bool allow_outside_uris) {
  const Asset asset = load_asset(input, {allow_outside_uris});
  return finish_preview(preview::render_preview(asset, options), options, input.string(), nullptr, out_dir);
}

}  // namespace gltf_pbr
