// LDR-FLIP (see flip.hpp). Equation and section numbers are the paper's.
#include "preview/flip.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <glm/vec3.hpp>

#include "core/color.hpp"
#include "preview/raster.hpp"

namespace gltf_pbr::preview {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Section 4: colour exponent q_c, feature exponent q_f, and the error redistribution's knee
// (p_c of the maximum colour error maps to p_t).
constexpr double kColorExponent = 0.7, kFeatureExponent = 0.5;
constexpr double kKneeInput = 0.4, kKneeOutput = 0.95;
// IEC 61966-2-1 D65 white of linear sRGB in XYZ.
constexpr double kWhiteX = 0.95047, kWhiteZ = 1.08883;

using Plane = std::vector<float>;
using Kernel = std::vector<float>;  // odd length, centred

// Section 4.1, equation 3: each opponent channel's contrast sensitivity is a sum of Gaussians
// a·sqrt(π/b)·exp(-π²r²/b), r in degrees. Table 1's (a1, b1, a2, b2) per channel.
struct CsfTerm {
  double a, b;
};
const std::array<std::vector<CsfTerm>, 3> kCsf = {{
    {{1.0, 0.0047}},                // achromatic
    {{1.0, 0.0053}},                // red-green
    {{34.1, 0.04}, {13.5, 0.025}},  // blue-yellow
}};

// One channel's CSF filter, as normalised separable terms with their weights (the 2-D filter is
// normalised to sum 1, as in the paper's reference code). The radius covers 3 standard deviations
// of the widest Gaussian of all channels.
std::vector<std::pair<double, Kernel>> csf_filter(int channel, double pixels_per_degree) {
  const double widest = 0.04;
  const int radius = static_cast<int>(std::ceil(3.0 * std::sqrt(widest / (2.0 * kPi * kPi)) * pixels_per_degree));
  std::vector<std::pair<double, Kernel>> terms;
  double total = 0;
  for (const CsfTerm& term : kCsf[static_cast<std::size_t>(channel)]) {
    Kernel kernel(static_cast<std::size_t>(2 * radius + 1));
    double sum = 0;
    for (int x = -radius; x <= radius; ++x) {
      const double degrees = x / pixels_per_degree;
      sum += kernel[static_cast<std::size_t>(x + radius)] =
          static_cast<float>(std::exp(-kPi * kPi * degrees * degrees / term.b));
    }
    for (float& tap : kernel) tap = static_cast<float>(tap / sum);
    const double weight = term.a * std::sqrt(kPi / term.b) * sum * sum;
    total += weight;
    terms.emplace_back(weight, std::move(kernel));
  }
  for (auto& term : terms) term.first /= total;
  return terms;
}

// Section 4.2: edges and points are the first and second derivatives of a Gaussian of standard
// deviation 0.5·w degrees, w = 0.082; positive and negative taps each normalised to ±1.
struct FeatureKernels {
  Kernel gaussian, edge, point;
};
FeatureKernels feature_kernels(double pixels_per_degree) {
  const double sd = 0.5 * 0.082 * pixels_per_degree;
  const int radius = static_cast<int>(std::ceil(3.0 * sd));
  FeatureKernels k;
  for (int x = -radius; x <= radius; ++x) {
    const double g = std::exp(-(x * x) / (2.0 * sd * sd));
    k.gaussian.push_back(static_cast<float>(g));
    k.edge.push_back(static_cast<float>(-x * g));
    k.point.push_back(static_cast<float>((x * x / (sd * sd) - 1.0) * g));
  }
  auto normalise_signs = [](Kernel& kernel) {
    double positive = 0, negative = 0;
    for (float tap : kernel) (tap > 0 ? positive : negative) += tap;
    for (float& tap : kernel) tap = static_cast<float>(tap > 0 ? tap / positive : tap < 0 ? tap / -negative : 0.0);
  };
  double sum = 0;
  for (float tap : k.gaussian) sum += tap;
  for (float& tap : k.gaussian) tap = static_cast<float>(tap / sum);
  normalise_signs(k.edge);
  normalise_signs(k.point);
  return k;
}

// Linear sRGB → YCxCz, the linearised CIELab of Section 4.1 (Lab without its cube root).
glm::dvec3 linear_srgb_to_ycxcz(glm::dvec3 rgb) {
  const double x = (0.4124564 * rgb.r + 0.3575761 * rgb.g + 0.1804375 * rgb.b) / kWhiteX;
  const double y = 0.2126729 * rgb.r + 0.7151522 * rgb.g + 0.0721750 * rgb.b;
  const double z = (0.0193339 * rgb.r + 0.1191920 * rgb.g + 0.9503041 * rgb.b) / kWhiteZ;
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

glm::dvec3 ycxcz_to_linear_srgb(glm::dvec3 ycxcz) {
  const double y = (ycxcz.x + 16.0) / 116.0;
  const double x = (ycxcz.y / 500.0 + y) * kWhiteX;
  const double z = (y - ycxcz.z / 200.0) * kWhiteZ;
  return {3.2404542 * x - 1.5371385 * y - 0.4985314 * z, -0.9692660 * x + 1.8760108 * y + 0.0415560 * z,
          0.0556434 * x - 0.2040259 * y + 1.0572252 * z};
}

// Section 4.1: Hunt-adjusted Lab (chroma scaled by 0.01·L) of a clamped linear sRGB colour.
glm::dvec3 hunt_lab(glm::dvec3 rgb) {
  const glm::dvec3 lab = linear_srgb_to_lab(glm::clamp(rgb, 0.0, 1.0));
  return {lab.x, 0.01 * lab.x * lab.y, 0.01 * lab.x * lab.z};
}

// Section 4.1: the HyAB distance (Abasi et al. 2020), lightness city-block, chroma Euclidean.
double hyab(glm::dvec3 a, glm::dvec3 b) { return std::fabs(a.x - b.x) + std::hypot(a.y - b.y, a.z - b.z); }

// FLIP runs over bands of rows, in parallel, each band in planes of its own thread that stay small
// at any image size. A band's own rows are [first, last); its input planes hold image rows
// [top, bottom), `halo` more either side, which the filters read. Only the columns near a
// difference are computed: a pixel farther than `halo` from every pixel where the images differ
// reads identical inputs through every filter, so its colour and feature differences are 0 and its
// error is exactly 0. The output columns [x0, x1) are the band's differing columns widened by the
// halo, and the input columns [in_x0, in_x1) those widened by it again. With halo >= every
// filter's radius each computed value is the whole-image value, bit for bit (the same taps summed
// in the same order, edges clamped at the image's borders).
struct Band {
  int first, last, top, bottom;
  int x0, x1, in_x0, in_x1;
  std::size_t rows() const { return static_cast<std::size_t>(bottom - top); }
  std::size_t own_rows() const { return static_cast<std::size_t>(last - first); }
  std::size_t out_width() const { return static_cast<std::size_t>(x1 - x0); }
  std::size_t in_width() const { return static_cast<std::size_t>(in_x1 - in_x0); }
};

struct Filters {
  std::array<std::vector<std::pair<double, Kernel>>, 3> csf;  // per opponent channel
  FeatureKernels features;
  int halo = 0;  // the widest filter's radius
};

// One thread's planes, reused from band to band: allocated once, never zeroed between uses.
struct Workspace {
  std::array<Plane, 3> ycxcz;  // input window, band rows
  Plane luminance;             // input window, band rows
  Plane across, padded;        // convolution scratch
  Plane term, along_x, along_y;
  std::array<Plane, 3> filtered_reference, filtered_test;  // output window, own rows
  Plane edges_reference, edges_test, points_reference, points_test;
};

// Separable convolution of an input-window plane: `along_rows` across each of the band's rows for
// the output columns, then `along_columns` down each output column for the band's own rows, into
// `out`. Both passes run tap by tap over contiguous spans, so the compiler vectorises them.
void convolve(const Plane& in, int width, int height, const Band& band, const Kernel& along_rows,
              const Kernel& along_columns, Workspace& ws, Plane& out) {
  const std::size_t in_w = band.in_width(), out_w = band.out_width();
  const int row_radius = static_cast<int>(along_rows.size() / 2),
            column_radius = static_cast<int>(along_columns.size() / 2);
  ws.across.resize(band.rows() * out_w);
  ws.padded.resize(out_w + 2 * static_cast<std::size_t>(row_radius));
  out.resize(band.own_rows() * out_w);
  for (std::size_t y = 0; y < band.rows(); ++y) {
    // The output columns' inputs, with the image's edge values repeated past its borders.
    const float* row = &in[y * in_w];
    for (std::size_t j = 0; j < ws.padded.size(); ++j)
      ws.padded[j] = row[std::clamp(band.x0 - row_radius + static_cast<int>(j), 0, width - 1) - band.in_x0];
    float* target = &ws.across[y * out_w];
    std::fill(target, target + out_w, 0.0f);
    for (std::size_t k = 0; k < along_rows.size(); ++k) {
      const float weight = along_rows[k];
      const float* source = &ws.padded[k];
      for (std::size_t x = 0; x < out_w; ++x) target[x] += weight * source[x];
    }
  }
  for (std::size_t own = 0; own < band.own_rows(); ++own) {
    const int y = band.first + static_cast<int>(own);
    float* target = &out[own * out_w];
    std::fill(target, target + out_w, 0.0f);
    for (int k = -column_radius; k <= column_radius; ++k) {
      const float weight = along_columns[static_cast<std::size_t>(k + column_radius)];
      const float* source = &ws.across[static_cast<std::size_t>(std::clamp(y + k, 0, height - 1) - band.top) * out_w];
      for (std::size_t x = 0; x < out_w; ++x) target[x] += weight * source[x];
    }
  }
}

// |∇| of the feature response: the length of the (x, y) pair of derivative filters.
void feature_magnitude(int width, int height, const Band& band, const Kernel& derivative, const Kernel& gaussian,
                       Workspace& ws, Plane& magnitude) {
  convolve(ws.luminance, width, height, band, derivative, gaussian, ws, ws.along_x);
  convolve(ws.luminance, width, height, band, gaussian, derivative, ws, ws.along_y);
  magnitude.resize(ws.along_x.size());
  for (std::size_t i = 0; i < magnitude.size(); ++i) magnitude[i] = std::hypot(ws.along_x[i], ws.along_y[i]);
}

// One image's CSF-filtered YCxCz (section 4.1) and edge and point magnitudes (section 4.2) over
// the band's output window.
void prepare(const std::vector<std::uint8_t>& image, int width, int height, const Band& band, const Filters& filters,
             Workspace& ws, std::array<Plane, 3>& filtered, Plane& edges, Plane& points) {
  const std::size_t in_w = band.in_width(), count = band.rows() * in_w;
  const auto& to_linear = srgb8_to_linear_table();
  for (Plane& plane : ws.ycxcz) plane.resize(count);
  ws.luminance.resize(count);
  for (std::size_t y = 0; y < band.rows(); ++y) {
    const std::uint8_t* pixels =
        &image[(static_cast<std::size_t>(band.top) + y) * static_cast<std::size_t>(width) * 3 + 3 * band.in_x0];
    for (std::size_t x = 0, i = y * in_w; x < in_w; ++x, ++i) {
      const glm::dvec3 c = linear_srgb_to_ycxcz(
          glm::dvec3(to_linear[pixels[x * 3]], to_linear[pixels[x * 3 + 1]], to_linear[pixels[x * 3 + 2]]));
      for (int k = 0; k < 3; ++k) ws.ycxcz[static_cast<std::size_t>(k)][i] = static_cast<float>(c[k]);
      ws.luminance[i] = static_cast<float>((c.x + 16.0) / 116.0);
    }
  }
  for (std::size_t channel = 0; channel < 3; ++channel) {
    Plane& out = filtered[channel];
    out.assign(band.own_rows() * band.out_width(), 0.0f);
    for (const auto& [weight, kernel] : filters.csf[channel]) {
      convolve(ws.ycxcz[channel], width, height, band, kernel, kernel, ws, ws.term);
      for (std::size_t i = 0; i < out.size(); ++i) out[i] += static_cast<float>(weight) * ws.term[i];
    }
  }
  feature_magnitude(width, height, band, filters.features.edge, filters.features.gaussian, ws, edges);
  feature_magnitude(width, height, band, filters.features.point, filters.features.gaussian, ws, points);
}

// The columns where two rows differ, [first, last]; first > last when they are equal.
std::pair<int, int> differing_columns(const std::uint8_t* a, const std::uint8_t* b, int width) {
  int first = 0, last = width - 1;
  while (first < width && std::memcmp(a + 3 * first, b + 3 * first, 3) == 0) ++first;
  while (last > first && std::memcmp(a + 3 * last, b + 3 * last, 3) == 0) --last;
  return {first, last};
}

}  // namespace

FlipResult flip(const std::vector<std::uint8_t>& reference, const std::vector<std::uint8_t>& test, int width,
                int height, double pixels_per_degree, int band_rows) {
  FlipResult result;
  const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (count == 0) return result;
  Filters filters;
  for (int channel = 0; channel < 3; ++channel)
    filters.csf[static_cast<std::size_t>(channel)] = csf_filter(channel, pixels_per_degree);
  filters.features = feature_kernels(pixels_per_degree);
  std::size_t widest = 0;
  for (const auto& channel : filters.csf)
    for (const auto& term : channel) widest = std::max(widest, term.second.size());
  widest =
      std::max({widest, filters.features.gaussian.size(), filters.features.edge.size(), filters.features.point.size()});
  const int halo = static_cast<int>(widest / 2);
  // 64 rows a band: its planes (some 60 bytes a pixel of the band's rows and halo) stay within a
  // few MB a thread for images up to a few thousand pixels wide.
  if (band_rows <= 0) band_rows = 64;

  // Section 4.1: the largest colour error, green against blue, anchors the redistribution.
  const double max_color_error = std::pow(hyab(hunt_lab({0.0, 1.0, 0.0}), hunt_lab({0.0, 0.0, 1.0})), kColorExponent);
  const double knee = kKneeInput * max_color_error;
  const std::size_t w = static_cast<std::size_t>(width);
  std::vector<std::pair<int, int>> row_differences(static_cast<std::size_t>(height));
  parallel_dynamic(height, [&](std::int64_t y) {
    const std::size_t at = static_cast<std::size_t>(y) * w * 3;
    row_differences[static_cast<std::size_t>(y)] = differing_columns(&reference[at], &test[at], width);
  });
  result.per_pixel.assign(count, 0.0f);
  std::vector<double> row_sums(static_cast<std::size_t>(height), 0.0);
  const int bands = (height + band_rows - 1) / band_rows;
  std::atomic<int> next_band{0};
  // One task per thread, each with its planes, taking bands in turn.
  parallel_dynamic(std::min<std::int64_t>(bands, hardware_threads()), [&](std::int64_t) {
    Workspace ws;
    for (int index; (index = next_band.fetch_add(1)) < bands;) {
      const int first = index * band_rows, last = std::min(height, first + band_rows);
      Band band{first, last, std::max(0, first - halo), std::min(height, last + halo), width, -1, 0, 0};
      for (int y = band.top; y < band.bottom; ++y) {  // differences within the halo of an own row
        const auto [from, to] = row_differences[static_cast<std::size_t>(y)];
        if (from <= to) band.x0 = std::min(band.x0, from), band.x1 = std::max(band.x1, to);
      }
      if (band.x0 > band.x1) continue;  // identical rows: every error is 0
      band.x0 = std::max(0, band.x0 - halo), band.x1 = std::min(width, band.x1 + 1 + halo);
      band.in_x0 = std::max(0, band.x0 - halo), band.in_x1 = std::min(width, band.x1 + halo);
      prepare(reference, width, height, band, filters, ws, ws.filtered_reference, ws.edges_reference,
              ws.points_reference);
      prepare(test, width, height, band, filters, ws, ws.filtered_test, ws.edges_test, ws.points_test);
      const std::size_t out_w = band.out_width();
      for (std::size_t own = 0; own < band.own_rows(); ++own) {
        double row_sum = 0;
        float* errors =
            &result.per_pixel[(static_cast<std::size_t>(first) + own) * w + static_cast<std::size_t>(band.x0)];
        for (std::size_t x = 0, i = own * out_w; x < out_w; ++x, ++i) {
          auto filtered_lab = [&](const std::array<Plane, 3>& filtered) {
            return hunt_lab(ycxcz_to_linear_srgb({filtered[0][i], filtered[1][i], filtered[2][i]}));
          };
          const double color =
              std::pow(hyab(filtered_lab(ws.filtered_reference), filtered_lab(ws.filtered_test)), kColorExponent);
          const double color_error =
              color < knee ? kKneeOutput / knee * color
                           : kKneeOutput + (color - knee) / (max_color_error - knee) * (1.0 - kKneeOutput);
          // Section 4.2: the larger of the edge and point differences, normalised by 1/sqrt(2).
          const double feature_difference = std::max(std::fabs(ws.edges_test[i] - ws.edges_reference[i]),
                                                     std::fabs(ws.points_test[i] - ws.points_reference[i])) /
                                            std::sqrt(2.0);
          const double feature_error = std::min(1.0, std::pow(feature_difference, kFeatureExponent));
          // Section 4.3, equation 10: features raise the colour error towards one.
          const double error = std::pow(color_error, 1.0 - feature_error);
          errors[x] = static_cast<float>(error);
          row_sum += error;
        }
        row_sums[static_cast<std::size_t>(first) + own] = row_sum;
      }
    }
  });
  double sum = 0;
  for (double row_sum : row_sums) sum += row_sum;
  result.mean = sum / static_cast<double>(count);
  return result;
}

}  // namespace gltf_pbr::preview
