// Times the material and texture checks over one asset and prints texels per second and the
// issues found. Usage: gltf_pbr_materials_timing [file.gltf] [repeats]; the default file is
// Avocado's spec-gloss version (2048^2 diffuse, specular-glossiness and normal maps).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <set>

#include "core/asset.hpp"
#include "core/image.hpp"
#include "core/material_model.hpp"
#include "rules/rule_set.hpp"
#include "validators/materials/materials.hpp"

gltf_pbr::MaterialCheckOptions materials_only() {
  gltf_pbr::MaterialCheckOptions options;
  options.textures = false;
  return options;
}

gltf_pbr::MaterialCheckOptions textures_only() {
  gltf_pbr::MaterialCheckOptions options;
  options.materials = false;
  return options;
}

int main(int argc, char** argv) {
  using namespace gltf_pbr;
  const fs::path file = argc > 1 && argv[1][0] != '\0'
                            ? fs::path(argv[1])
                            : fs::path(GLTF_PBR_SHARED_DIR) / "assets/Avocado/specgloss/Avocado.gltf";
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  Asset asset;
  try {
    asset = load_asset(file);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 1;
  }
  long long texels = 0;
  double best_ms = 1e30;
  Report report;
  for (int run = 0; run < repeats; ++run) {
    Report this_run;
    const long decodes_before = work_counters().images_decoded.load();
    const auto start = std::chrono::steady_clock::now();
    validate_materials(asset, builtin_rules(), materials_only(), this_run);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("run %d: %.1f ms, %ld images decoded\n", run, ms,
                work_counters().images_decoded.load() - decodes_before);
    best_ms = std::min(best_ms, ms);
    report = std::move(this_run);
  }
  for (const auto& issue : report.messages) {
    std::printf("%s %s %s: %s\n", severity_name(issue.severity), issue.code.c_str(), issue.pointer.c_str(),
                issue.message.c_str());
    const auto at = issue.message.find(" texels (");
    if (at != std::string::npos) {
      const auto from = issue.message.rfind("% of ", at);
      texels = std::max(texels, std::atoll(issue.message.c_str() + from + 5));
    }
  }
  // Decoding alone, of the images the materials' reflectance reads, to separate it from the checks.
  double decode_ms = 0;
  {
    std::set<int> images;
    for (int index = 0; index < static_cast<int>(asset.model.materials.size()); ++index)
      for (const MaterialTexture& texture : read_material_inputs(asset.model, index).textures)
        if (texture.present()) images.insert(texture.image);
    const auto start = std::chrono::steady_clock::now();
    for (int image : images) (void)decode_image(encoded_image_bytes(asset, image), "image");
    decode_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  // Texel count of the largest evaluated grid (all materials of Avocado share one).
  std::printf("PBR checks: best %.1f ms with decode; decoding every image alone %.1f ms", best_ms, decode_ms);
  if (texels > 0)
    std::printf("\n  %.1f Mtexels/s with decode, ~%.1f Mtexels/s checks only (%lld texels)",
                static_cast<double>(texels) / best_ms / 1000.0,
                static_cast<double>(texels) / std::max(1.0, best_ms - decode_ms) / 1000.0, texels);
  std::printf("\n");

  Report textures;
  const auto start = std::chrono::steady_clock::now();
  validate_materials(asset, builtin_rules(), textures_only(), textures);
  std::printf("IMAGE checks (decode included): %.1f ms\n",
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  for (const auto& issue : textures.messages)
    std::printf("%s %s %s: %s\n", severity_name(issue.severity), issue.code.c_str(), issue.pointer.c_str(),
                issue.message.c_str());
  return 0;
}
