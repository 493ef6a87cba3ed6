// The preview pipeline: convert in memory, rasterize once, resolve both G-buffers, light, compare.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <sstream>

#include "converter/solver.hpp"
#include "core/color.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "core/json_pointer.hpp"
#include "core/texel_buffer.hpp"
#include "preview/flip.hpp"
#include "preview/preview.hpp"

namespace gltf_pbr::preview {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

nlohmann::json camera_json(const Camera& c, const std::string& source) {
  return {{"source", source},
          {"eye", {c.eye.x, c.eye.y, c.eye.z}},
          {"forward", {c.forward.x, c.forward.y, c.forward.z}},
          {"vertical_fov_degrees", 2.0 * std::atan(c.tan_half_fov_y) * 180.0 / 3.14159265358979},
          {"orthographic", c.orthographic}};
}

nlohmann::json layout_json(const std::vector<BufferSize>& layout) {
  nlohmann::json buffers = nlohmann::json::array();
  int total = 0;
  for (const auto& b : layout) {
    buffers.push_back({{"buffer", b.name}, {"bytes_per_pixel", b.bytes_per_pixel}});
    total += b.bytes_per_pixel;
  }
  return {{"bytes_per_pixel", total}, {"buffers", buffers}};
}

// The environment a preview lights with: the built-in sky, the one read once for a run of
// previews, or its file read now into `loaded`.
const Environment& lighting_environment(const PreviewOptions& options, std::optional<Environment>& loaded) {
  if (options.environment.empty()) return default_environment();
  if (options.loaded_environment) return *options.loaded_environment;
  return loaded.emplace(load_environment(options.environment));
}

}  // namespace

PreviewResult light_and_compare(GBuffers gbuffers, const Camera& camera, const Environment& env,
                                const PreviewOptions& options) {
  PreviewResult result;
  result.width = gbuffers.after.width;
  result.height = gbuffers.after.height;
  result.before_layout = gbuffers.before.layout();
  result.after_layout = gbuffers.after.layout();
  auto start = Clock::now();
  {
    LitPair lit = light_both(gbuffers, env, camera, options.lighting, options.keep_radiance);
    GBuffers released = std::move(gbuffers);  // the largest buffers, done with before the metrics
    result.before = std::move(lit.before);
    result.after = std::move(lit.after);
    result.covered = std::move(lit.covered);
    result.before_hdr = std::move(lit.before_hdr);
    result.after_hdr = std::move(lit.after_hdr);
  }
  result.times.lighting_ms = ms_since(start);
  start = Clock::now();
  {
    std::vector<float> delta_e;
    result.metrics = compare_images(result.before, result.after, result.covered, result.width, result.height, &delta_e);
    result.difference = heat_map(delta_e, result.covered, result.after);
  }
  result.metrics.flip_mean = flip(result.before, result.after, result.width, result.height).mean;
  result.sheet = side_by_side({&result.before, &result.after, &result.difference}, result.width, result.height, 4,
                              &result.sheet_width);
  result.times.metrics_ms = ms_since(start);
  result.camera = camera_json(camera, camera.orthographic ? "grid" : "");
  return result;
}

PreviewResult render_preview(const Asset& asset, const PreviewOptions& options) {
  const TexelPageReuse reuse;  // the render's buffers take the pages of the conversion's maps
  const auto start = Clock::now();
  Asset converted = asset;
  DecodedImages decoded;  // the conversion's pixels, which the scene then does not decode again
  ConvertOptions convert_options = options.convert;
  convert_options.keep_decoded = &decoded;
  ConversionReport conversion = convert(converted, convert_options);
  const double convert_ms = ms_since(start);
  if (options.on_converted) options.on_converted(converted, decoded);
  PreviewResult result = render_pair(asset, converted, options, &decoded);
  result.times.convert_ms = convert_ms;
  result.conversion = std::move(conversion);
  return result;
}

PreviewResult render_pair(const Asset& asset, const Asset& converted, const PreviewOptions& options,
                          DecodedImages* decoded) {
  const TexelPageReuse reuse;  // the G-buffers take the pages of the pixels, the visibility buffer's
  auto start = Clock::now();
  // Textures wait for the raster, which tells the levels the pixels sample (alpha-tested ones aside).
  Scene scene = build_scene(asset, converted, decoded, TextureLoading::SampledLevelsLater);
  if (decoded) decoded->clear();  // the scene holds what it still needs of the conversion's pixels
  double scene_ms = ms_since(start);

  start = Clock::now();
  std::optional<Environment> loaded;
  const Environment& env = lighting_environment(options, loaded);
  const double environment_ms = ms_since(start);

  const double aspect = static_cast<double>(options.width) / options.height;
  Camera camera;
  std::string camera_source = "framed on scene bounds";
  if (options.gltf_camera >= 0) {
    if (options.gltf_camera >= static_cast<int>(scene.cameras.size())) {
      const bool orthographic = std::any_of(asset.model.cameras.begin(), asset.model.cameras.end(),
                                            [](const tinygltf::Camera& c) { return c.type == "orthographic"; });
      throw InputError(asset.path.string(), "/cameras",
                       "camera " + std::to_string(options.gltf_camera) + " requested, the scene has " +
                           std::to_string(scene.cameras.size()) + " perspective camera(s)" +
                           (orthographic ? " (orthographic cameras are not drawn through)" : ""));
    }
    const SceneCamera& chosen = scene.cameras[static_cast<size_t>(options.gltf_camera)];
    // The camera schema: yfov and znear above 0; and yfov below π, past which no perspective
    // projection exists. A view through anything else shows nothing, no fault of the scene's.
    constexpr float kPi = 3.14159265358979323846f;
    const auto short_number = [](float value) { return (std::ostringstream() << value).str(); };
    if (!(chosen.yfov > 0.0f && chosen.yfov < kPi) || !(chosen.znear > 0.0f))
      throw InputError(asset.path.string(), pointer("cameras", chosen.index) + "/perspective",
                       "cannot draw through this camera: yfov " + short_number(chosen.yfov) + " and znear " +
                           short_number(chosen.znear) + " (yfov must be in (0, pi), znear above 0)");
    camera = camera_from_gltf(chosen, aspect);
    camera_source = "glTF camera " + std::to_string(options.gltf_camera);
  } else {
    camera = frame_camera(scene.bounds, options.yaw_degrees, options.pitch_degrees, options.fov_y_degrees, aspect);
  }

  start = Clock::now();
  RasterStats raster_stats;
  double raster_ms = 0;
  GBuffers gbuffers;
  {  // the visibility buffer lives only until the G-buffers are filled
    const VisibilityBuffer visibility = rasterize(scene, camera, options.width, options.height, &raster_stats);
    raster_ms = ms_since(start);
    start = Clock::now();
    if (scene.unloaded) load_textures(scene, finest_sampled_levels(scene, visibility, camera));
    scene_ms += ms_since(start);
    start = Clock::now();
    gbuffers = fill_gbuffers(scene, visibility, camera);
  }
  const double gbuffer_ms = ms_since(start);

  PreviewResult result = light_and_compare(std::move(gbuffers), camera, env, options);
  result.camera = camera_json(camera, camera_source);
  result.times.scene_ms = scene_ms;
  result.times.environment_ms = environment_ms;
  result.times.raster_ms = raster_ms;
  result.times.gbuffer_ms = gbuffer_ms;
  result.scene = scene.stats;
  result.raster = raster_stats;
  return result;
}

GBuffers sphere_gbuffers(std::span<const SpherePair> spheres, int columns, int cell, Camera* camera) {
  GBuffers out;
  const int rows = (static_cast<int>(spheres.size()) + columns - 1) / columns;
  const int width = columns * cell, height = rows * cell;
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
  for (GBuffer* g : {&out.before, &out.after}) {
    g->width = width;
    g->height = height;
    g->depth.assign(count, std::numeric_limits<float>::infinity());
    g->normal.assign(count, NormalAndScalar{0});
  }
  out.after.albedo.assign(count, AlbedoMetalness{});
  out.before.diffspec.assign(count, DiffuseSpecular{});
  auto unorm8 = [](float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  auto srgb8 = [](float v) { return encode_srgb8(v); };
  const float radius = 0.42f * static_cast<float>(cell);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t sphere = static_cast<size_t>((y / cell) * columns + x / cell);
      if (sphere >= spheres.size()) continue;
      const float lx = (static_cast<float>(x % cell) + 0.5f - 0.5f * static_cast<float>(cell)) / radius;
      const float ly = (static_cast<float>(y % cell) + 0.5f - 0.5f * static_cast<float>(cell)) / radius;
      const float r2 = lx * lx + ly * ly;
      if (r2 >= 1.0f) continue;
      // Orthographic view down -Z: the visible hemisphere's normal is (x, y, sqrt(1 - x^2 - y^2)).
      const glm::vec3 normal(lx, -ly, std::sqrt(1.0f - r2));
      const SpecGloss& legacy = spheres[sphere].before;
      const MetalRough& core = spheres[sphere].after;
      const size_t i = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
      out.after.depth[i] = out.before.depth[i] = 1.0f;
      out.after.normal[i] = pack_normal_and_scalar(normal, core.roughness);
      out.before.normal[i] = pack_normal_and_scalar(normal, legacy.glossiness);
      out.after.albedo[i] = {{srgb8(core.base.x), srgb8(core.base.y), srgb8(core.base.z)}, unorm8(core.metalness)};
      out.before.diffspec[i] = {{srgb8(legacy.diffuse.x), srgb8(legacy.diffuse.y), srgb8(legacy.diffuse.z)},
                                {srgb8(legacy.specular.x), srgb8(legacy.specular.y), srgb8(legacy.specular.z)}};
    }
  if (camera) {
    *camera = Camera{};
    camera->orthographic = true;
    camera->eye = glm::dvec3(0, 0, 10);
    camera->aspect = static_cast<double>(width) / height;
  }
  return out;
}

GBuffers sphere_grid_gbuffers(const GridOptions& grid, Camera* camera) {
  std::vector<SpherePair> spheres;
  for (int row = 0; row < grid.rows; ++row)
    for (int column = 0; column < grid.columns; ++column) {
      const MetalRough core{
          grid.albedo, grid.rows > 1 ? static_cast<float>(row) / static_cast<float>(grid.rows - 1) : 0.0f,
          grid.columns > 1 ? static_cast<float>(column) / static_cast<float>(grid.columns - 1) : 0.5f};
      spheres.push_back({to_spec_gloss(core), core});
    }
  return sphere_gbuffers(spheres, grid.columns, grid.cell, camera);
}

PreviewResult render_grid(const GridOptions& grid, const PreviewOptions& options) {
  std::optional<Environment> loaded;
  const Environment& env = lighting_environment(options, loaded);
  Camera camera;
  const auto start = Clock::now();
  GBuffers gbuffers = sphere_grid_gbuffers(grid, &camera);
  const double gbuffer_ms = ms_since(start);
  PreviewResult result = light_and_compare(std::move(gbuffers), camera, env, options);
  result.times.gbuffer_ms = gbuffer_ms;
  return result;
}

nlohmann::json preview_report(const PreviewResult& r, const PreviewOptions& options) {
  const double megapixels = static_cast<double>(r.width) * r.height / 1e6;
  nlohmann::json report;
  report["width"] = r.width;
  report["height"] = r.height;
  report["camera"] = r.camera;
  report["shading"] = {
      {"after", "glTF 2.0 Appendix B: GGX, height-correlated Smith, Schlick; diffuse (1 - F) weighted"},
      {"before",
       options.lighting.legacy_reading_b
           ? "KHR_materials_pbrSpecularGlossiness reading B: c_diff = diffuse (1 - max specular), (1 - F) weighted"
           : "KHR_materials_pbrSpecularGlossiness reading A: c_diff = diffuse (1 - max specular), under the "
             "dielectric layer's (1 - F(0.04)) normalised to 1 at normal incidence"},
      // What the after side's conversion matched (--error-model; the names of api/names.cpp).
      {"conversion_error_model",
       options.convert.solver.error_model == ErrorModel::Appearance ? "appearance" : "normal-incidence"},
      {"specular_lobe", options.lighting.lobe == SpecularLobe::Ggx ? "ggx" : "blinn-phong"},
      {"environment", options.environment.empty() ? "built-in procedural sky + sun" : options.environment.string()},
      {"sun", options.lighting.sun},
      {"tone_map", options.lighting.tone_map == ToneMap::KhronosPbrNeutral ? "khronos-pbr-neutral"
                   : options.lighting.tone_map == ToneMap::Aces            ? "aces"
                                                                           : "clamp"},
      {"exposure", options.lighting.exposure}};
  report["gbuffer"] = {{"before", layout_json(r.before_layout)}, {"after", layout_json(r.after_layout)}};
  // What the process really held at its peak (getrusage), beside what the G-buffers alone need: the
  // bytes per pixel above are the G-buffer layout, not the cost of a preview.
  const double gbuffer_bytes = static_cast<double>(r.width) * r.height *
                               (layout_json(r.before_layout)["bytes_per_pixel"].get<int>() +
                                layout_json(r.after_layout)["bytes_per_pixel"].get<int>());
  struct rusage usage {};
  const bool measured = ::getrusage(RUSAGE_SELF, &usage) == 0;
  const double peak = static_cast<double>(usage.ru_maxrss) * 1024.0;  // Linux reports KiB
  report["memory"] = {{"process_peak_rss_bytes", measured ? nlohmann::json(peak) : nlohmann::json(nullptr)},
                      {"gbuffers_bytes", gbuffer_bytes},
                      {"note",
                       "the process's peak so far (getrusage), not this preview's alone: under "
                       "convert --preview it includes the conversions and other files"}};
  // A picture of nothing has no difference to measure: its figures are null, not 0, and no pass.
  const bool compared = r.metrics.pixels_compared > 0;
  const auto measured_figure = [&](auto value) { return compared ? nlohmann::json(value) : nlohmann::json(nullptr); };
  report["difference"] = {
      {"delta_e_2000",
       {{"mean", measured_figure(r.metrics.delta_e_mean)},
        {"p95", measured_figure(r.metrics.delta_e_p95)},
        {"max", measured_figure(r.metrics.delta_e_max)}}},
      {"flip", {{"mean", measured_figure(r.metrics.flip_mean)}, {"pixels_per_degree", kFlipPixelsPerDegree}}},
      {"rms_db", measured_figure(r.metrics.rms_db)},
      {"rms_db_fail_above", -22.0},
      {"rms_pass", measured_figure(r.metrics.rms_db <= -22.0)},
      {"pixels_compared", r.metrics.pixels_compared}};
  const PreviewTimes& t = r.times;
  report["times_ms"] = {{"convert", t.convert_ms}, {"scene", t.scene_ms},     {"environment", t.environment_ms},
                        {"raster", t.raster_ms},   {"gbuffer", t.gbuffer_ms}, {"lighting_both_sides", t.lighting_ms},
                        {"metrics", t.metrics_ms}};
  report["ms_per_megapixel"] = {{"gbuffer_pass", t.gbuffer_pass_ms() / megapixels},
                                {"lighting_per_side", t.lighting_ms / 2.0 / megapixels}};
  report["scene"] = {{"triangles", r.scene.triangles},
                     {"vertices", r.scene.vertices},
                     {"meshes_drawn", r.scene.meshes_drawn},
                     {"draco_primitives", r.scene.draco_primitives},
                     {"skipped_primitives", r.scene.skipped_primitives},
                     {"skinned_primitives", r.scene.skinned_primitives},
                     {"morphed_primitives", r.scene.morphed_primitives},
                     {"textures_decoded", r.scene.textures_decoded},
                     {"textures_from_conversion", r.scene.textures_from_conversion},
                     {"uses_emission", r.scene.uses_emission},
                     {"uses_occlusion", r.scene.uses_occlusion},
                     {"triangles_culled", r.raster.culled},
                     {"triangles_clipped", r.raster.clipped},
                     {"warnings", r.scene.warnings}};
  if (r.conversion) {
    nlohmann::json materials = nlohmann::json::array();
    for (const auto& m : r.conversion->materials) {
      nlohmann::json error_a = nullptr;
      if (m.error_a)
        error_a = {{"diffuse_p95", m.error_a->diffuse.p95},
                   {"f0_p95", m.error_a->f0.p95},
                   {"appearance_p95", m.error_a->appearance ? nlohmann::json(m.error_a->appearance->p95) : nullptr}};
      materials.push_back({{"index", m.index},
                           {"name", m.name},
                           {"outcome", material_outcome_name(m.outcome)},
                           {"note", m.note},
                           {"texel_delta_e_2000_a", std::move(error_a)},
                           {"time_ms", m.times.total()}});
    }
    report["conversion"] = {{"materials", materials}, {"warnings", r.conversion->warnings}};
  }
  report["images"] = {{"before", "before.png"},
                      {"after", "after.png"},
                      {"difference", "difference.png"},
                      {"sheet", "sheet.png (before | after | difference)"},
                      {"difference_scale", "ΔE2000: black 0, blue 2.5, green 5, yellow 7.5, red >= 10"}};
  return report;
}

std::vector<fs::path> write_preview(const PreviewResult& r, const nlohmann::json& report, const fs::path& folder) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  AtomicWriteSet files;
  files.stage(folder / "before.png", encode_png(r.before, r.width, r.height, 3, 6));
  files.stage(folder / "after.png", encode_png(r.after, r.width, r.height, 3, 6));
  files.stage(folder / "difference.png", encode_png(r.difference, r.width, r.height, 3, 6));
  files.stage(folder / "sheet.png", encode_png(r.sheet, r.sheet_width, r.height, 3, 6));
  const std::string text = report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  files.stage(folder / "report.json", std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  return files.commit();
}

}  // namespace gltf_pbr::preview
