// Texel error statistics: ΔE2000 of the diffuse weight and of F0 between the legacy material and
// its conversion (the error model of solver.hpp), as mean, 95th percentile and maximum.
#pragma once
#include <vector>

#include "converter/solver.hpp"

namespace gltf_pbr {

struct ErrorStats {
  double mean = 0.0, p95 = 0.0, max = 0.0;
};

struct ReflectanceError {
  ErrorStats diffuse, f0;
  double worst() const { return diffuse.max > f0.max ? diffuse.max : f0.max; }
};

class ErrorAccumulator {
 public:
  ErrorAccumulator() = default;
  // Room for `samples` samples, each then written once by set(), from any thread: a bake knows
  // its sample count up front and needs no per-thread parts to merge.
  explicit ErrorAccumulator(size_t samples) : diffuse_(samples), f0_(samples) {}
  void add(const Reflectance& expected, const Reflectance& actual);
  void set(size_t sample, const Reflectance& expected, const Reflectance& actual);
  void set(size_t sample, float diffuse_delta_e, float f0_delta_e);  // already computed ΔE2000 values
  ReflectanceError finish();  // reorders the samples (a partial sort for the percentile)
  size_t samples() const { return diffuse_.size(); }

 private:
  std::vector<float> diffuse_, f0_;
};

}  // namespace gltf_pbr
