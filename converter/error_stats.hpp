// Texel error statistics: ΔE2000 of the diffuse weight and of F0 between the legacy material and
// its conversion, and of their appearance (the error models of solver.hpp), as mean, 95th
// percentile and maximum.
#pragma once
#include <optional>
#include <vector>

#include "converter/solver.hpp"

namespace gltf_pbr {

struct ErrorStats {
  double mean = 0.0, p95 = 0.0, max = 0.0;
};

struct ReflectanceError {
  ErrorStats diffuse, f0;
  // The mean over the appearance rings of ΔE2000 between the two materials' radiance; only where
  // measured (reading A of a solve), else none, never a 0.
  std::optional<ErrorStats> appearance;
  double worst() const { return diffuse.max > f0.max ? diffuse.max : f0.max; }
};

class ErrorAccumulator {
 public:
  ErrorAccumulator() = default;
  // Room for `samples` samples, each then written once by set(), from any thread: a bake knows
  // its sample count up front and needs no per-thread parts to merge.
  // With `appearance`, each sample also takes its appearance error (set_appearance).
  explicit ErrorAccumulator(size_t samples, bool appearance = false)
      : diffuse_(samples), f0_(samples), appearance_(appearance ? samples : 0) {}
  void add(const Reflectance& expected, const Reflectance& actual);
  void add(const Appearance& expected, const Appearance& actual);  // a sample's appearance error
  void set(size_t sample, const Reflectance& expected, const Reflectance& actual);
  void set(size_t sample, float diffuse_delta_e, float f0_delta_e);  // already computed ΔE2000 values
  void set_appearance(size_t sample, float delta_e) { appearance_[sample] = delta_e; }
  ReflectanceError finish();  // reorders the samples (a partial sort for the percentile)
  // judged_error (below) of the samples as they are, from their means alone: nothing reordered.
  double judged(ErrorModel model) const;
  size_t samples() const { return diffuse_.size(); }

 private:
  std::vector<float> diffuse_, f0_, appearance_;
};

// ΔE2000 between two appearances: the mean over the rings (each an equal share of a sphere).
float appearance_delta_e(const Appearance& expected, const Appearance& actual);

// The one figure by which a choice between two ways of writing a material is judged, the error
// model's own: the sum of the diffuse and F0 means at normal incidence, the appearance mean under
// the appearance model (where measured).
double judged_error(const ReflectanceError& error, ErrorModel model);

}  // namespace gltf_pbr
