// Preview render time per image (figures only): the G-buffer pass (raster + material resolve)
// and the lighting pass (both sides in one sweep), at 512^2 and 1024^2, in ms per megapixel.
// Each stage reports wall time (best of REPEATS) and process CPU time (all threads): on a shared
// machine the CPU figure divided by the core count is the unloaded wall time.
//   gltf-pbr-preview-bench [ASSETS_DIR] [REPEATS] [SIZES] [ASSET]
// SIZES is a comma-separated list (default 512,1024); ASSET keeps only the assets whose name
// contains it (for profiling one asset under valgrind --tool=callgrind).
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "preview/preview.hpp"

using namespace gltf_pbr;
using namespace gltf_pbr::preview;

namespace {

struct Clocks {
  double wall_ms, cpu_ms;
};

double cpu_now_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

template <typename Work>
Clocks measure(int repeats, const Work& work) {
  Clocks best{1e30, 1e30};
  for (int r = 0; r < repeats; ++r) {
    const auto wall = std::chrono::steady_clock::now();
    const double cpu = cpu_now_ms();
    work();
    best.wall_ms = std::min(best.wall_ms,
                            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall).count());
    best.cpu_ms = std::min(best.cpu_ms, cpu_now_ms() - cpu);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path assets = argc > 1 ? fs::path(argv[1]) : fs::path("/work/shared/assets");
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  std::vector<int> sizes;
  std::stringstream size_list(argc > 3 ? argv[3] : "512,1024");
  for (std::string item; std::getline(size_list, item, ',');)
    if (std::atoi(item.c_str()) > 0) sizes.push_back(std::atoi(item.c_str()));
  const std::string only = argc > 4 ? argv[4] : "";
  const char* files[] = {"Avocado/specgloss/Avocado.gltf", "CesiumMilkTruck/specgloss/CesiumMilkTruck.gltf",
                         "2CylinderEngine/specgloss/2CylinderEngine.gltf", "VC/specgloss/VC.gltf"};
  const Environment& env = default_environment();  // baked at build time; not part of a frame
  (void)dfg_lookup(0.5f, 0.5f);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  std::printf("%u hardware threads; ms per megapixel, wall (best of %d) / CPU over all threads\n", cores, repeats);
  std::printf("%-16s %5s %7s | %15s %15s | %15s %15s | %s\n", "asset", "size", "tris", "raster wall/cpu",
              "resolve wall/cpu", "gbuffer ms/MP", "light/side ms/MP", "total ms/MP (wall; cpu/cores)");
  for (const char* file : files) {
    if (std::string(file).find(only) == std::string::npos) continue;
    const Asset asset = load_asset(assets / file);
    Asset converted = asset;
    convert(converted);
    const Scene scene = build_scene(asset, converted);
    for (int size : sizes) {
      const Camera camera = frame_camera(scene.bounds, 35, 20, 40, 1.0);
      VisibilityBuffer visibility;
      GBuffers gbuffers;
      const Clocks raster = measure(repeats, [&] { visibility = rasterize(scene, camera, size, size); });
      const Clocks resolve = measure(repeats, [&] { gbuffers = fill_gbuffers(scene, visibility, camera); });
      LightingOptions lighting;
      const Clocks light = measure(repeats, [&] {
        const LitPair lit = light_both(gbuffers, env, camera, lighting);  // tone-mapped in the same pass
        (void)lit;
      });
      const double mp = size * static_cast<double>(size) / 1e6;
      const double gbuffer_wall = (raster.wall_ms + resolve.wall_ms) / mp;
      const double gbuffer_cpu = (raster.cpu_ms + resolve.cpu_ms) / mp / cores;
      const double light_wall = light.wall_ms / 2.0 / mp, light_cpu = light.cpu_ms / 2.0 / mp / cores;
      std::printf("%-16s %5d %7lld | %6.1f / %6.1f %6.1f / %6.1f | %6.1f; %6.1f %7.1f; %6.1f | %6.1f; %6.1f\n",
                  fs::path(file).stem().string().c_str(), size, static_cast<long long>(scene.triangles.size()),
                  raster.wall_ms, raster.cpu_ms, resolve.wall_ms, resolve.cpu_ms, gbuffer_wall, gbuffer_cpu, light_wall,
                  light_cpu, gbuffer_wall + light_wall, gbuffer_cpu + light_cpu);
    }
  }
  return 0;
}
