// Difference figures and pictures (see metrics.hpp).
#include "preview/metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/vec3.hpp>
#include <vector>

#include "core/color.hpp"
#include "preview/raster.hpp"

namespace gltf_pbr::preview {

DifferenceMetrics compare_images(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                                 const std::vector<std::uint8_t>& covered, int width, int height,
                                 std::vector<float>* delta_e_per_pixel) {
  DifferenceMetrics m;
  const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
  const std::array<float, 256>& linear_of = srgb8_to_linear_table();
  std::vector<float> delta_e(count, 0.0f);
  // Row by row, the covered pixels' colours in CIELAB and their ΔE2000 in SIMD batches.
  parallel_dynamic(height, [&](std::int64_t y) {
    const size_t first = static_cast<size_t>(y) * static_cast<size_t>(width);
    std::vector<size_t> pixels;
    std::vector<glm::vec3> linear_a, linear_b;
    for (size_t i = first; i < first + static_cast<size_t>(width); ++i) {
      if (!covered[i]) continue;
      pixels.push_back(i);
      linear_a.emplace_back(linear_of[a[i * 3]], linear_of[a[i * 3 + 1]], linear_of[a[i * 3 + 2]]);
      linear_b.emplace_back(linear_of[b[i * 3]], linear_of[b[i * 3 + 1]], linear_of[b[i * 3 + 2]]);
    }
    std::vector<glm::vec3> lab_a(pixels.size()), lab_b(pixels.size());
    std::vector<float> row(pixels.size());
    linear_srgb_to_lab(linear_a, lab_a);
    linear_srgb_to_lab(linear_b, lab_b);
    delta_e_2000(lab_a, lab_b, row);
    for (size_t k = 0; k < pixels.size(); ++k) delta_e[pixels[k]] = row[k];
  });
  std::vector<float> values;
  double sum_squares = 0;
  for (size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double d = (a[i * 3 + static_cast<size_t>(c)] - b[i * 3 + static_cast<size_t>(c)]) / 255.0;
      sum_squares += d * d;
    }
    if (covered[i]) values.push_back(delta_e[i]);
  }
  const double rms = std::sqrt(sum_squares / static_cast<double>(std::max<size_t>(1, count * 3)));
  m.rms_db = rms > 1e-10 ? 20.0 * std::log10(rms) : -200.0;
  m.pixels_compared = static_cast<long long>(values.size());
  if (!values.empty()) {
    double sum = 0;
    for (float v : values) sum += v;
    m.delta_e_mean = sum / static_cast<double>(values.size());
    const size_t p95 =
        std::min(values.size() - 1, static_cast<size_t>(std::ceil(0.95 * static_cast<double>(values.size()))) - 1);
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(p95), values.end());
    m.delta_e_p95 = values[p95];
    m.delta_e_max = *std::max_element(values.begin(), values.end());
  }
  if (delta_e_per_pixel) *delta_e_per_pixel = std::move(delta_e);
  return m;
}

std::vector<std::uint8_t> heat_map(const std::vector<float>& delta_e, const std::vector<std::uint8_t>& covered,
                                   const std::vector<std::uint8_t>& context, float full_scale) {
  static const glm::vec3 stops[5] = {
      {0, 0, 0}, {0.1f, 0.25f, 1.0f}, {0.1f, 0.85f, 0.2f}, {1.0f, 0.9f, 0.1f}, {1.0f, 0.1f, 0.05f}};
  std::vector<std::uint8_t> out(delta_e.size() * 3);
  for (size_t i = 0; i < delta_e.size(); ++i) {
    glm::vec3 c;
    if (covered[i]) {
      const float t = std::clamp(delta_e[i] / full_scale, 0.0f, 1.0f) * 4.0f;
      const int k = std::min(3, static_cast<int>(t));
      c = glm::mix(stops[k], stops[k + 1], t - static_cast<float>(k)) * 255.0f;
    } else {
      c = glm::vec3(context[i * 3], context[i * 3 + 1], context[i * 3 + 2]) * 0.2f;
    }
    for (int k = 0; k < 3; ++k) out[i * 3 + static_cast<size_t>(k)] = static_cast<std::uint8_t>(std::lround(c[k]));
  }
  return out;
}

std::vector<std::uint8_t> side_by_side(const std::vector<const std::vector<std::uint8_t>*>& images, int width,
                                       int height, int gap, int* sheet_width) {
  const int n = static_cast<int>(images.size());
  const int total = n * width + (n - 1) * gap;
  std::vector<std::uint8_t> out(static_cast<size_t>(total) * static_cast<size_t>(height) * 3, 24);
  for (int k = 0; k < n; ++k)
    for (int y = 0; y < height; ++y)
      std::copy_n(images[static_cast<size_t>(k)]->begin() + static_cast<std::ptrdiff_t>(y) * width * 3, width * 3,
                  out.begin() + (static_cast<std::ptrdiff_t>(y) * total + k * (width + gap)) * 3);
  if (sheet_width) *sheet_width = total;
  return out;
}

}  // namespace gltf_pbr::preview
