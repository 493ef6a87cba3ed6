// Image difference figures and pictures: CIEDE2000 per pixel, RMS in dB, a heat map and a
// side-by-side sheet.
#pragma once
#include <cstdint>
#include <vector>

namespace gltf_pbr::preview {

struct DifferenceMetrics {
  double delta_e_mean = 0, delta_e_p95 = 0, delta_e_max = 0;  // CIEDE2000 over pixels either side covers
  double rms_db = -200;                                       // over all pixels; see compare_images
  double flip_mean = 0;                                       // LDR-FLIP over all pixels (flip.hpp)
  long long pixels_compared = 0;
};

// a, b: 8-bit sRGB RGB images of one size. ΔE2000 compares the displayed colours (decoded to
// linear sRGB, then CIE Lab D65). RMS-dB is 20 log10 of the root mean square of the per-channel
// difference of the 8-bit values normalised to [0, 1], over the whole image, as image-comparison
// tools for renderer fidelity report it (Khronos glTF-Render-Fidelity flags worse than -22 dB).
DifferenceMetrics compare_images(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                                 const std::vector<std::uint8_t>& covered, int width, int height,
                                 std::vector<float>* delta_e_per_pixel = nullptr);

// ΔE2000 as colour: black 0, blue 2.5, green 5, yellow 7.5, red >= 10; uncovered pixels show the
// `context` image darkened to a fifth.
std::vector<std::uint8_t> heat_map(const std::vector<float>& delta_e, const std::vector<std::uint8_t>& covered,
                                   const std::vector<std::uint8_t>& context, float full_scale = 10.0f);

// Images of one size side by side, separated by `gap` dark pixels; returns the sheet's width.
std::vector<std::uint8_t> side_by_side(const std::vector<const std::vector<std::uint8_t>*>& images, int width,
                                       int height, int gap, int* sheet_width);

}  // namespace gltf_pbr::preview
