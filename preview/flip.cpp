// LDR-FLIP (see flip.hpp). Equation and section numbers are the paper's.
#include "preview/flip.hpp"

#include <algorithm>
#include <array>
#include <cmath>
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

// FLIP runs over bands of rows so that its planes (some 60 bytes a pixel) stay bounded at any image
// size. A band's own rows are [first, last); its planes hold image rows [top, bottom), up to
// `halo` more either side, which the filters read. With halo >= every filter's radius the result
// is the whole-image result, bit for bit (the sums run in the same order).
struct Band {
  int first, last, top, bottom, height;
  std::size_t rows() const { return static_cast<std::size_t>(bottom - top); }
  std::size_t own_rows() const { return static_cast<std::size_t>(last - first); }
};

// Separable convolution with edges clamped at the image's borders: `along_rows` across each of the
// band's rows, then `along_columns` down each column, for the band's own rows. Both passes run
// over contiguous spans so the compiler vectorises them.
Plane convolve(const Plane& in, int width, const Band& band, const Kernel& along_rows, const Kernel& along_columns) {
  const std::size_t w = static_cast<std::size_t>(width);
  Plane across(in.size()), out(band.own_rows() * w);
  const int row_radius = static_cast<int>(along_rows.size() / 2),
            column_radius = static_cast<int>(along_columns.size() / 2);
  parallel_dynamic(static_cast<std::int64_t>(band.rows()), [&](std::int64_t y) {
    // The row with its edge values repeated `row_radius` times on each side.
    std::vector<float> padded(w + 2 * static_cast<std::size_t>(row_radius));
    const float* row = &in[static_cast<std::size_t>(y) * w];
    for (std::size_t x = 0; x < padded.size(); ++x)
      padded[x] = row[std::clamp<std::int64_t>(static_cast<std::int64_t>(x) - row_radius, 0, width - 1)];
    float* target = &across[static_cast<std::size_t>(y) * w];
    for (std::size_t x = 0; x < w; ++x) {
      float sum = 0;
      for (std::size_t k = 0; k < along_rows.size(); ++k) sum += along_rows[k] * padded[x + k];
      target[x] = sum;
    }
  });
  parallel_dynamic(static_cast<std::int64_t>(band.own_rows()), [&](std::int64_t own) {
    const int y = band.first + static_cast<int>(own);
    float* target = &out[static_cast<std::size_t>(own) * w];
    std::fill(target, target + w, 0.0f);
    for (int k = -column_radius; k <= column_radius; ++k) {
      const float weight = along_columns[static_cast<std::size_t>(k + column_radius)];
      const int source_row = std::clamp(y + k, 0, band.height - 1) - band.top;
      const float* source = &across[static_cast<std::size_t>(source_row) * w];
      for (std::size_t x = 0; x < w; ++x) target[x] += weight * source[x];
    }
  });
  return out;
}

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

struct Prepared {
  std::array<Plane, 3> filtered;  // YCxCz after the CSF, the band's own rows
  Plane luminance;                // normalised Y in [0, 1], for the features, all the band's rows
};

Prepared prepare(const std::vector<std::uint8_t>& image, int width, const Band& band, double pixels_per_degree) {
  const std::size_t w = static_cast<std::size_t>(width), count = band.rows() * w;
  const auto& to_linear = srgb8_to_linear_table();
  std::array<Plane, 3> ycxcz;
  for (Plane& plane : ycxcz) plane.resize(count);
  Prepared p;
  p.luminance.resize(count);
  const std::uint8_t* pixels = &image[static_cast<std::size_t>(band.top) * w * 3];
  parallel_dynamic(static_cast<std::int64_t>(band.rows()), [&](std::int64_t y) {
    for (std::size_t i = static_cast<std::size_t>(y) * w, end = i + w; i < end; ++i) {
      const glm::dvec3 c = linear_srgb_to_ycxcz(
          glm::dvec3(to_linear[pixels[i * 3]], to_linear[pixels[i * 3 + 1]], to_linear[pixels[i * 3 + 2]]));
      for (int k = 0; k < 3; ++k) ycxcz[static_cast<std::size_t>(k)][i] = static_cast<float>(c[k]);
      p.luminance[i] = static_cast<float>((c.x + 16.0) / 116.0);
    }
  });
  for (int channel = 0; channel < 3; ++channel) {
    Plane& out = p.filtered[static_cast<std::size_t>(channel)];
    out.assign(band.own_rows() * w, 0.0f);
    for (const auto& [weight, kernel] : csf_filter(channel, pixels_per_degree)) {
      const Plane term = convolve(ycxcz[static_cast<std::size_t>(channel)], width, band, kernel, kernel);
      for (std::size_t i = 0; i < out.size(); ++i) out[i] += static_cast<float>(weight) * term[i];
    }
  }
  return p;
}

// |∇| of the feature response: the length of the (x, y) pair of derivative filters.
Plane feature_magnitude(const Plane& luminance, int width, const Band& band, const Kernel& derivative,
                        const Kernel& gaussian) {
  const Plane along_x = convolve(luminance, width, band, derivative, gaussian);
  const Plane along_y = convolve(luminance, width, band, gaussian, derivative);
  Plane magnitude(along_x.size());
  for (std::size_t i = 0; i < magnitude.size(); ++i) magnitude[i] = std::hypot(along_x[i], along_y[i]);
  return magnitude;
}

// The rows either side of a band that the widest filter reads.
int filter_halo(double pixels_per_degree) {
  std::size_t widest = 0;
  for (int channel = 0; channel < 3; ++channel)
    for (const auto& term : csf_filter(channel, pixels_per_degree)) widest = std::max(widest, term.second.size());
  const FeatureKernels kernels = feature_kernels(pixels_per_degree);
  widest = std::max({widest, kernels.gaussian.size(), kernels.edge.size(), kernels.point.size()});
  return static_cast<int>(widest / 2);
}

}  // namespace

FlipResult flip(const std::vector<std::uint8_t>& reference, const std::vector<std::uint8_t>& test, int width,
                int height, double pixels_per_degree, int band_rows) {
  FlipResult result;
  const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (count == 0) return result;
  const FeatureKernels kernels = feature_kernels(pixels_per_degree);
  const int halo = filter_halo(pixels_per_degree);
  // About a million pixels a band: some 70 MB of planes, and few enough bands that the halo's
  // extra rows stay a small share.
  if (band_rows <= 0) band_rows = std::max(2 * halo, (1 << 20) / width);

  // Section 4.1: the largest colour error, green against blue, anchors the redistribution.
  const double max_color_error = std::pow(hyab(hunt_lab({0.0, 1.0, 0.0}), hunt_lab({0.0, 0.0, 1.0})), kColorExponent);
  const double knee = kKneeInput * max_color_error;
  result.per_pixel.resize(count);
  const std::size_t w = static_cast<std::size_t>(width);
  std::vector<double> row_sums(static_cast<std::size_t>(height));
  for (int first = 0; first < height; first += band_rows) {
    const int last = std::min(height, first + band_rows);
    const Band band{first, last, std::max(0, first - halo), std::min(height, last + halo), height};
    const Prepared r = prepare(reference, width, band, pixels_per_degree);
    const Prepared t = prepare(test, width, band, pixels_per_degree);
    const Plane edges_r = feature_magnitude(r.luminance, width, band, kernels.edge, kernels.gaussian);
    const Plane edges_t = feature_magnitude(t.luminance, width, band, kernels.edge, kernels.gaussian);
    const Plane points_r = feature_magnitude(r.luminance, width, band, kernels.point, kernels.gaussian);
    const Plane points_t = feature_magnitude(t.luminance, width, band, kernels.point, kernels.gaussian);
    parallel_dynamic(static_cast<std::int64_t>(band.own_rows()), [&](std::int64_t own) {
      double row_sum = 0;
      for (std::size_t i = static_cast<std::size_t>(own) * w, end = i + w; i < end; ++i) {
        auto filtered_lab = [&](const Prepared& p) {
          return hunt_lab(ycxcz_to_linear_srgb({p.filtered[0][i], p.filtered[1][i], p.filtered[2][i]}));
        };
        const double color = std::pow(hyab(filtered_lab(r), filtered_lab(t)), kColorExponent);
        const double color_error = color < knee
                                       ? kKneeOutput / knee * color
                                       : kKneeOutput + (color - knee) / (max_color_error - knee) * (1.0 - kKneeOutput);
        // Section 4.2: the larger of the edge and point differences, normalised by 1/sqrt(2).
        const double feature_difference =
            std::max(std::fabs(edges_t[i] - edges_r[i]), std::fabs(points_t[i] - points_r[i])) / std::sqrt(2.0);
        const double feature_error = std::min(1.0, std::pow(feature_difference, kFeatureExponent));
        // Section 4.3, equation 10: features raise the colour error towards one.
        const double error = std::pow(color_error, 1.0 - feature_error);
        result.per_pixel[static_cast<std::size_t>(first) * w + i] = static_cast<float>(error);
        row_sum += error;
      }
      row_sums[static_cast<std::size_t>(first + own)] = row_sum;
    });
  }
  double sum = 0;
  for (double row_sum : row_sums) sum += row_sum;
  result.mean = sum / static_cast<double>(count);
  return result;
}

}  // namespace gltf_pbr::preview
