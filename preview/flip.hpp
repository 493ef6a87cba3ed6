// LDR-FLIP: the perceptual difference of two images as they alternate on a screen.
// Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild, "FLIP: A Difference Evaluator
// for Alternating Images", Proc. ACM Comput. Graph. Interact. Tech. 3(2), HPG 2020.
#pragma once
#include <cstdint>
#include <vector>

namespace gltf_pbr::preview {

// The paper's default viewing condition: a 0.7 m wide 4K monitor seen from 0.7 m (section 5).
inline constexpr double kFlipPixelsPerDegree = 67.0;

struct FlipResult {
  std::vector<float> per_pixel;  // in [0, 1], row-major
  double mean = 0;
};

// reference, test: 8-bit sRGB RGB images of one size. The filters run over bands of `band_rows`
// rows (0: 64), in parallel, so memory stays bounded whatever the size, and only near the pixels
// where the images differ (elsewhere the error is exactly 0); the result does not depend on the
// band size.
FlipResult flip(const std::vector<std::uint8_t>& reference, const std::vector<std::uint8_t>& test, int width,
                int height, double pixels_per_degree = kFlipPixelsPerDegree, int band_rows = 0);

}  // namespace gltf_pbr::preview
