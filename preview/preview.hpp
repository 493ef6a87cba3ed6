// preview: draws an asset twice, as its legacy spec-gloss materials ("before") and as their
// in-process conversion to albedo + metalness ("after"), with a CPU deferred renderer, and
// measures the difference (GitHub issue 5; DESIGN.md "Preview renderer").
#pragma once
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "converter/convert.hpp"
#include "core/asset.hpp"
#include "preview/environment.hpp"
#include "preview/gbuffer.hpp"
#include "preview/lighting.hpp"
#include "preview/metrics.hpp"
#include "preview/raster.hpp"
#include "preview/scene.hpp"

namespace gltf_pbr::preview {

struct PreviewOptions {
  int width = 512, height = 512;
  int gltf_camera = -1;  // >= 0: draw through the asset's N-th perspective camera (scene order)
  double yaw_degrees = 35, pitch_degrees = 20, fov_y_degrees = 40;  // the automatic framing
  LightingOptions lighting;
  std::filesystem::path environment;  // .hdr / .exr; empty: the built-in procedural sky
  // `environment` read once for a run of previews (preview DIR): used instead of reading it again.
  std::shared_ptr<const Environment> loaded_environment;
  ConvertOptions convert;
  bool keep_radiance = false;   // keep PreviewResult::before_hdr/after_hdr (24 bytes a pixel more)
  // Called by render_preview between its conversion and the scene, with the conversion and the
  // pixels decoded so far (the input's maps the conversion read, its baked maps), which the scene
  // reuses and then frees: a step that also reads the textures (preview --lint) decodes none again.
  std::function<void(const Asset& converted, DecodedImages& decoded)> on_converted;
};

// --grid: spheres in a metalness (rows, top 0 to bottom 1) x roughness (columns, left 0 to
// right 1) array of one albedo; "before" is each sphere's to_spec_gloss image.
struct GridOptions {
  glm::vec3 albedo{0.9f, 0.6f, 0.2f};  // linear
  int rows = 5, columns = 5;
  int cell = 128;  // pixels per sphere cell
};

struct PreviewTimes {
  double convert_ms = 0, scene_ms = 0, environment_ms = 0;
  double raster_ms = 0, gbuffer_ms = 0, lighting_ms = 0;  // lighting: both sides + tone mapping
  double metrics_ms = 0;
  double gbuffer_pass_ms() const { return raster_ms + gbuffer_ms; }
};

struct PreviewResult {
  int width = 0, height = 0;
  std::vector<std::uint8_t> before, after, difference;  // 8-bit sRGB RGB
  std::vector<std::uint8_t> sheet;                      // before | after | difference
  int sheet_width = 0;
  std::vector<std::uint8_t> covered;
  HdrImage before_hdr, after_hdr;  // empty unless PreviewOptions::keep_radiance
  std::vector<BufferSize> before_layout, after_layout;
  DifferenceMetrics metrics;
  PreviewTimes times;
  SceneStats scene;
  RasterStats raster;
  std::optional<ConversionReport> conversion;
  nlohmann::json camera;
};

// Converts a copy of `asset` in memory, draws both sides, compares them. Throws InputError for
// bad input and std::runtime_error for an unreadable environment.
PreviewResult render_preview(const Asset& asset, const PreviewOptions& options);
// The same for a conversion already made (gltf-pbr convert --preview): `asset` drawn as "before",
// `converted` as "after"; result.conversion stays empty (convert --preview sets it to its report).
// `decoded`: the pixels the conversion kept (ConvertOptions::keep_decoded), not decoded again;
// emptied once the scene is built, so they do not stay in memory through the render.
PreviewResult render_pair(const Asset& asset, const Asset& converted, const PreviewOptions& options,
                          DecodedImages* decoded = nullptr);
PreviewResult render_grid(const GridOptions& grid, const PreviewOptions& options);

// The common tail: both G-buffers lit, tone-mapped and compared (used by tests with analytic
// G-buffers too). The G-buffers are taken, and released once lit.
PreviewResult light_and_compare(GBuffers gbuffers, const Camera& camera, const Environment& env,
                                const PreviewOptions& options);

// Analytic spheres, one (before, after) material pair per cell of `cell` pixels, `columns` to a row,
// seen orthographically down -Z; for --grid (before = to_spec_gloss(after)) and tests.
struct SpherePair {
  SpecGloss before;
  MetalRough after;
};
GBuffers sphere_gbuffers(std::span<const SpherePair> spheres, int columns, int cell, Camera* camera);
GBuffers sphere_grid_gbuffers(const GridOptions& grid, Camera* camera);

// The files of a preview's folder, as write_preview names them.
inline constexpr const char* kPreviewFiles[] = {"before.png", "after.png", "difference.png", "sheet.png",
                                                "report.json"};
// kPreviewFiles into `folder`, atomically; returns the files written.
std::vector<fs::path> write_preview(const PreviewResult& result, const nlohmann::json& report, const fs::path& folder);
nlohmann::json preview_report(const PreviewResult& result, const PreviewOptions& options);

}  // namespace gltf_pbr::preview
