// Times solve_batch, one thread, under each error model and preset, on the same generated
// materials: the per-solve cost that the bake pays on every cache miss. Runs alternate between
// the models, and the median of the runs is printed with the ratio to normal incidence.
//   cmake --build build --target solver-bench && build/bench/solver/solver-bench [materials] [runs]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <utility>
#include <vector>

#include "converter/solver.hpp"

using namespace gltf_pbr;

int main(int argc, char** argv) {
  const int count = std::max(1, argc > 1 ? std::atoi(argv[1]) : 65536);
  const int runs = std::max(1, argc > 2 ? std::atoi(argv[2]) : 9);
  // Texture-like inputs: diffuse anywhere in the cube, grey and tinted specular up to 1.1 (past
  // gold's), glossiness anywhere: the appearance model's terms depend on it.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), specular(0.0f, 1.1f);
  std::vector<SpecGloss> materials;
  for (int i = 0; i < count; ++i) {
    float draws[8];  // drawn in order: a constructor's arguments are evaluated in any order
    for (int k = 0; k < 3; ++k) draws[k] = unit(rng);
    for (int k = 3; k < 7; ++k) draws[k] = specular(rng);
    draws[7] = unit(rng);
    const glm::vec3 diffuse(draws[0], draws[1], draws[2]), tinted(draws[3], draws[4], draws[5]);
    materials.push_back({diffuse, i % 2 ? tinted : glm::vec3(draws[6]), draws[7]});
  }
  std::vector<MetalRough> out(materials.size());
  std::printf("%d materials, %d runs each, one thread; median ns per solve\n", count, runs);
  std::printf("%-9s %18s %12s %7s\n", "preset", "normal-incidence", "appearance", "ratio");
  const std::pair<SolverEffort, const char*> presets[] = {
      {SolverEffort::Fast, "fast"}, {SolverEffort::Balanced, "balanced"}, {SolverEffort::Exact, "exact"}};
  for (const auto& [effort, name] : presets) {
    std::vector<double> seconds[2];
    for (int run = 0; run < runs; ++run)
      for (int model = 0; model < 2; ++model) {
        const SolverSettings settings =
            solver_preset(effort, model == 0 ? ErrorModel::NormalIncidence : ErrorModel::Appearance);
        const auto start = std::chrono::steady_clock::now();
        solve_batch(materials, out, settings);
        seconds[model].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
    double median[2];
    for (int model = 0; model < 2; ++model) {
      std::sort(seconds[model].begin(), seconds[model].end());
      median[model] = seconds[model][seconds[model].size() / 2] * 1e9 / count;
    }
    std::printf("%-9s %18.0f %12.0f %7.2f\n", name, median[0], median[1], median[1] / median[0]);
  }
}
