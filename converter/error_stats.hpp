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
  void add(const Reflectance& expected, const Reflectance& actual);
  void add(float diffuse_delta_e, float f0_delta_e);  // already computed ΔE2000 values
  void merge(const ErrorAccumulator& other);
  ReflectanceError finish() const;
  size_t samples() const { return diffuse_.size(); }

 private:
  std::vector<float> diffuse_, f0_;
};

}  // namespace gltf_pbr
