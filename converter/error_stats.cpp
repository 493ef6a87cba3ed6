#include "converter/error_stats.hpp"

#include <algorithm>

#include "core/color.hpp"
#include "core/parallel.hpp"

namespace gltf_pbr {
namespace {

double delta_e(glm::vec3 a, glm::vec3 b) {
  return delta_e_2000(linear_srgb_to_lab(glm::dvec3(a)), linear_srgb_to_lab(glm::dvec3(b)));
}

double mean_of(const std::vector<float>& values) {
  double sum = 0.0;
  for (const float v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

ErrorStats summarise(std::vector<float>& values) {
  ErrorStats stats;
  if (values.empty()) return stats;
  stats.mean = mean_of(values);
  // Nearest-rank percentile.
  const size_t rank = std::min(values.size() - 1, static_cast<size_t>(0.95 * static_cast<double>(values.size())));
  const auto p95 = values.begin() + static_cast<std::ptrdiff_t>(rank);
  std::nth_element(values.begin(), p95, values.end());
  stats.p95 = *p95;
  stats.max = *std::max_element(p95, values.end());  // nth_element left the larger values after it
  return stats;
}

}  // namespace

void ErrorAccumulator::add(const Reflectance& expected, const Reflectance& actual) {
  diffuse_.push_back(static_cast<float>(delta_e(expected.diffuse, actual.diffuse)));
  f0_.push_back(static_cast<float>(delta_e(expected.f0, actual.f0)));
}

void ErrorAccumulator::set(size_t sample, const Reflectance& expected, const Reflectance& actual) {
  set(sample, static_cast<float>(delta_e(expected.diffuse, actual.diffuse)),
      static_cast<float>(delta_e(expected.f0, actual.f0)));
}

void ErrorAccumulator::set(size_t sample, float diffuse_delta_e, float f0_delta_e) {
  diffuse_[sample] = diffuse_delta_e;
  f0_[sample] = f0_delta_e;
}

void ErrorAccumulator::add(const Appearance& expected, const Appearance& actual) {
  appearance_.push_back(appearance_delta_e(expected, actual));
}

ReflectanceError ErrorAccumulator::finish() {
  // The figures' summaries are independent, each a partial sort of its samples: a texture's take
  // them on the pool (a bake finishes two accumulators, VC's 21 bakes 84 sorts of 65,536 samples).
  constexpr size_t kSamplesWorthAThread = 4096;
  std::vector<float>* const figures[] = {&diffuse_, &f0_, &appearance_};
  ErrorStats stats[3];
  const auto summarise_figure = [&](std::int64_t k) { stats[k] = summarise(*figures[k]); };
  const std::int64_t count = appearance_.empty() ? 2 : 3;
  if (diffuse_.size() >= kSamplesWorthAThread)
    parallel_dynamic(count, summarise_figure);
  else
    for (std::int64_t k = 0; k < count; ++k) summarise_figure(k);
  ReflectanceError error{stats[0], stats[1], std::nullopt};
  if (!appearance_.empty()) error.appearance = stats[2];
  return error;
}

float appearance_delta_e(const Appearance& expected, const Appearance& actual) {
  double sum = 0.0;
  for (int k = 0; k < kAppearanceRings; ++k) sum += delta_e(expected.ring[k], actual.ring[k]);
  return static_cast<float>(sum / kAppearanceRings);
}

namespace {

double judged_of(ErrorModel model, double diffuse_mean, double f0_mean, std::optional<double> appearance_mean) {
  return model == ErrorModel::Appearance && appearance_mean ? *appearance_mean : diffuse_mean + f0_mean;
}

}  // namespace

double ErrorAccumulator::judged(ErrorModel model) const {
  return judged_of(model, mean_of(diffuse_), mean_of(f0_),
                   appearance_.empty() ? std::nullopt : std::optional<double>(mean_of(appearance_)));
}

double judged_error(const ReflectanceError& error, ErrorModel model) {
  return judged_of(model, error.diffuse.mean, error.f0.mean,
                   error.appearance ? std::optional<double>(error.appearance->mean) : std::nullopt);
}

}  // namespace gltf_pbr
