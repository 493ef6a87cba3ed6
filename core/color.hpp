// Colour math: sRGB transfer functions and CIE ΔE2000.
#pragma once
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>

namespace gltf_pbr {

// IEC 61966-2-1 sRGB transfer functions, on [0, 1] (values outside are clamped first).
float srgb_to_linear(float encoded);
float linear_to_srgb(float linear);

// srgb_to_linear of every 8-bit code (code / 255), computed once: decoding 8-bit texels is the hot
// case (baking, material checks, preview sampling) and a lookup replaces a pow per channel.
const std::array<float, 256>& srgb8_to_linear_table();
float srgb8_to_linear(std::uint8_t code);

// CIE L*a*b* (D65 white) from linear sRGB; XYZ matrix from IEC 61966-2-1.
glm::dvec3 linear_srgb_to_lab(glm::dvec3 rgb);

// CIEDE2000 colour difference (Sharma, Wu, Dalal 2005, "The CIEDE2000 Color-Difference Formula").
double delta_e_2000(glm::dvec3 lab1, glm::dvec3 lab2);

// The same two in float SIMD lanes, for many colours at once (error statistics, difference maps).
// Cube root, arctangent, sine and exponential are Cephes-style polynomials (Moshier, "Methods and
// Programs for Mathematical Functions", 1989) good to a few float ulps, so each result agrees
// with the double-precision function above to float rounding (tests/color_test.cpp bounds it),
// not bit for bit, and never depends on the other colours of the batch. Where CIEDE2000 is itself
// discontinuous (a grey's hue is its a*, b* rounding noise; hues 180° apart) the two may differ
// by more: up to 0.05 against a grey. A NaN in gives NaN out. Spans are of one length.
void linear_srgb_to_lab(std::span<const glm::vec3> linear, std::span<glm::vec3> lab);
void delta_e_2000(std::span<const glm::vec3> lab1, std::span<const glm::vec3> lab2, std::span<float> delta_e);

}  // namespace gltf_pbr
