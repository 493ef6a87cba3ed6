// Colour math: sRGB transfer functions and CIE ΔE2000.
#pragma once
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>

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

}  // namespace gltf_pbr
