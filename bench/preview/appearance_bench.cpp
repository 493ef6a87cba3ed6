// Which error model previews closer to the legacy look (issue 12), figures only:
//   gltf-pbr-appearance-bench [ASSETS_DIR] [SIZE] [sky|neutral|ENVIRONMENT]
// Lit by the built-in sky and sun (the default), by a neutral environment (a uniform white one
// without a sun, the white furnace, in which every direction mirrors the same grey), or by an
// equirectangular .hdr or .exr (bench/preview/appearance_environments.sh runs Blender's worlds).
// 1. Every shared spec-gloss asset drawn by the preview (SIZE² pixels) as
//    its legacy materials and as three conversions: ours with the normal-incidence and with the
//    appearance error model, and the lossless dielectric route (base = diffuse, metallic 0, the
//    KHR_materials_specular and _ior extensions dropped: what a core-only viewer shows of
//    glTF-Transform's metalrough output). ΔE2000 mean and p95 and FLIP mean of before against
//    after, and the solve time of each model.
// 2. Grey dielectric spheres (specular 0, 0.02, 0.1, 0.2 over 7 diffuse colours, glossiness 0.2,
//    0.5, 0.8), before against after for both models: the mean ΔE2000 over each sphere. For each
//    level's worst sphere under the appearance model, the lowest a brute-force search reaches over
//    core materials base = clamp(a diffuse + b), metalness m (a in [0.5, 1.4], b in [-0.06, 0.3],
//    m in [0, 1] in steps of 0.1; roughness 1 - glossiness: offsets of -0.2 to +0.45 never lowered
//    it): an estimate of the floor a core material leaves.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "converter/convert.hpp"
#include "preview/preview.hpp"

using namespace gltf_pbr;
using namespace gltf_pbr::preview;

namespace {

double solve_ms(const PreviewResult& result) {
  double ms = 0;
  if (result.conversion)
    for (const MaterialReport& m : result.conversion->materials) ms += m.times.solve_ms;
  return ms;
}

// The lossless dielectric route as a core-only viewer reads it.
Asset core_only_dielectric(const Asset& legacy) {
  Asset copy = legacy;
  ConvertOptions options;
  options.target = Target::Specular;
  options.specular_tolerance = -1.0;  // every material takes the extension route
  (void)convert(copy, options);
  for (tinygltf::Material& material : copy.model.materials) {
    material.extensions.erase("KHR_materials_specular");
    material.extensions.erase("KHR_materials_ior");
  }
  return copy;
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path assets = argc > 1 ? fs::path(argv[1]) : fs::path("/work/shared/assets");
  const int size = argc > 2 ? std::atoi(argv[2]) : 256;
  const std::string lighting = argc > 3 ? argv[3] : "sky";
  if (size < 16 || size > 8192) {
    std::fprintf(stderr, "usage: gltf-pbr-appearance-bench [ASSETS_DIR] [SIZE in 16-8192] [sky|neutral|ENVIRONMENT]\n");
    return 2;
  }
  // render_preview takes a loaded environment under its name, never reading the file again.
  std::shared_ptr<const Environment> loaded;
  if (lighting == "neutral")
    loaded = std::make_shared<const Environment>(uniform_environment(glm::vec3(1.0f)));
  else if (lighting != "sky") {
    try {
      loaded = std::make_shared<const Environment>(load_environment(lighting));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "gltf-pbr-appearance-bench: %s\n", e.what());
      return 1;
    }
  }
  const Environment& environment = loaded ? *loaded : default_environment();
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(assets))
    if (entry.path().parent_path().filename() == "specgloss" && entry.path().extension() == ".gltf")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  PreviewOptions options;
  options.width = options.height = size;
  if (loaded) {
    options.environment = lighting;
    options.loaded_environment = loaded;
  }
  std::printf("Environment: %s\n\n", lighting == "sky"       ? "the built-in sky and sun"
                                     : lighting == "neutral" ? "neutral (uniform white, no sun)"
                                                             : lighting.c_str());
  std::printf("| asset | normal-incidence ΔE mean / p95 / FLIP | appearance ΔE mean / p95 / FLIP | "
              "core-only dielectric ΔE mean / p95 / FLIP | solve ms normal-incidence / appearance |\n"
              "|---|---|---|---|---|\n");
  for (const fs::path& file : files) {
    const Asset asset = load_asset(file);
    PreviewResult by_model[2];
    for (int k = 0; k < 2; ++k) {
      options.convert.solver = solver_preset(SolverEffort::Balanced,
                                             k == 0 ? ErrorModel::NormalIncidence : ErrorModel::Appearance);
      by_model[k] = render_preview(asset, options);
    }
    const PreviewResult dielectric = render_pair(asset, core_only_dielectric(asset), options);
    const auto figures = [](const PreviewResult& r) {
      char text[64];
      std::snprintf(text, sizeof text, "%.2f / %.2f / %.4f", r.metrics.delta_e_mean, r.metrics.delta_e_p95,
                    r.metrics.flip_mean);
      return std::string(text);
    };
    std::printf("| %s | %s | %s | %s | %.1f / %.1f |\n", file.stem().c_str(), figures(by_model[0]).c_str(),
                figures(by_model[1]).c_str(), figures(dielectric).c_str(), solve_ms(by_model[0]),
                solve_ms(by_model[1]));
  }

  const glm::vec3 diffuses[] = {glm::vec3(0.05f), glm::vec3(0.2f), glm::vec3(0.5f),          glm::vec3(0.8f),
                                {0.8f, 0.05f, 0.05f}, {0.8f, 0.6f, 0.1f}, {0.1f, 0.25f, 0.7f}};
  const auto sphere_delta_e = [&](const SpherePair& sphere) {
    Camera camera;
    return light_and_compare(sphere_gbuffers(std::span(&sphere, 1), 1, 96, &camera), camera, environment, options)
        .metrics.delta_e_mean;
  };
  std::printf("\n| specular | normal-incidence sphere ΔE mean: mean / worst | appearance: mean / worst | "
              "searched floor of the appearance model's worst sphere |\n|---|---|---|---|\n");
  for (const float specular : {0.0f, 0.02f, 0.1f, 0.2f}) {
    double sum[2] = {0, 0}, worst[2] = {0, 0};
    SpecGloss worst_sphere;
    int count = 0;
    for (const glm::vec3 diffuse : diffuses)
      for (const float gloss : {0.2f, 0.5f, 0.8f}) {
        const SpecGloss legacy{diffuse, glm::vec3(specular), gloss};
        for (int k = 0; k < 2; ++k) {
          const double delta_e = sphere_delta_e(
              {legacy, solve(legacy, solver_preset(SolverEffort::Balanced,
                                                   k == 0 ? ErrorModel::NormalIncidence : ErrorModel::Appearance))});
          sum[k] += delta_e;
          if (delta_e > worst[k]) {
            worst[k] = delta_e;
            if (k == 1) worst_sphere = legacy;
          }
        }
        ++count;
      }
    double floor = 1e30;
    for (float a = 0.5f; a <= 1.401f; a += 0.9f / 14)
      for (float b = -0.06f; b <= 0.301f; b += 0.03f)
        for (float m = 0.0f; m <= 1.001f; m += 0.1f)
          floor = std::min(floor, sphere_delta_e({worst_sphere,
                                                  {glm::clamp(a * worst_sphere.diffuse + b, 0.0f, 1.0f), m,
                                                   1.0f - worst_sphere.glossiness}}));
    std::printf("| %.2f | %.2f / %.2f | %.2f / %.2f | %.2f (diffuse %.2f,%.2f,%.2f, glossiness %.1f) |\n", specular,
                sum[0] / count, worst[0], sum[1] / count, worst[1], floor, worst_sphere.diffuse.r,
                worst_sphere.diffuse.g, worst_sphere.diffuse.b, worst_sphere.glossiness);
  }
}
