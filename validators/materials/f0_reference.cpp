#include "validators/materials/f0_reference.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/color.hpp"

namespace gltf_pbr {
namespace {

// Within this CIEDE2000 difference an F0 "is" the entry: 2 is about a just noticeable difference
// side by side (Sharma 2005), and rounding the table to 2 decimals stays well inside it.
constexpr double kSameAsEntry = 2.0;

constexpr glm::vec3 grey(float v) { return glm::vec3(v); }

const std::array<F0Reference, 16> kReferences{{
    // Dielectrics: DESIGN.md "Why albedo + metalness": water 0.02, plastic and glass 0.04-0.045,
    // crystal and gems 0.05-0.08, diamond-like 0.10-0.20, crystalline silicon ~0.35-0.43.
    {"water", grey(0.02f), grey(0.02f), false},
    {"plastic or glass", grey(0.04f), grey(0.045f), false},
    {"crystal or gem", grey(0.05f), grey(0.08f), false},
    {"diamond-like gem", grey(0.10f), grey(0.20f), false},
    {"crystalline silicon (semiconductor)", grey(0.35f), grey(0.43f), false},
    // Metals: Hoffman's measured linear F0.
    {"Titanium", {0.542f, 0.497f, 0.449f}, {0.542f, 0.497f, 0.449f}, true},
    {"Chromium", {0.549f, 0.556f, 0.554f}, {0.549f, 0.556f, 0.554f}, true},
    {"Iron", {0.562f, 0.565f, 0.578f}, {0.562f, 0.565f, 0.578f}, true},
    {"Nickel", {0.660f, 0.609f, 0.526f}, {0.660f, 0.609f, 0.526f}, true},
    {"Platinum", {0.673f, 0.637f, 0.585f}, {0.673f, 0.637f, 0.585f}, true},
    {"Silver", {0.972f, 0.960f, 0.915f}, {0.972f, 0.960f, 0.915f}, true},
    {"Copper", {0.955f, 0.638f, 0.538f}, {0.955f, 0.638f, 0.538f}, true},
    {"Palladium", {0.733f, 0.697f, 0.652f}, {0.733f, 0.697f, 0.652f}, true},
    {"Zinc", {0.664f, 0.824f, 0.850f}, {0.664f, 0.824f, 0.850f}, true},
    {"Gold", {1.022f, 0.782f, 0.344f}, {1.022f, 0.782f, 0.344f}, true},
    {"Aluminum", {0.913f, 0.922f, 0.924f}, {0.913f, 0.922f, 0.924f}, true},
}};

}  // namespace

std::span<const F0Reference> f0_references() { return kReferences; }

const F0Reference& nearest_f0_reference(glm::vec3 f0, double* distance) {
  // Resemblance is what the eye sees: CIEDE2000 between the F0 colours, to the nearest point of a
  // dielectric class's range.
  const glm::dvec3 lab = linear_srgb_to_lab(glm::dvec3(f0));
  const F0Reference* best = &kReferences[0];
  double best_distance = INFINITY;
  for (const F0Reference& entry : kReferences) {
    const double d = delta_e_2000(lab, linear_srgb_to_lab(glm::dvec3(glm::clamp(f0, entry.low, entry.high))));
    if (d < best_distance) best_distance = d, best = &entry;
  }
  if (distance) *distance = best_distance;
  return *best;
}

std::string format_number(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string format_rgb(glm::vec3 value, int decimals) {
  const std::string r = format_number(value.r, decimals), g = format_number(value.g, decimals),
                    b = format_number(value.b, decimals);
  if (r == g && g == b) return r;
  return "(" + r + ", " + g + ", " + b + ")";
}

std::string describe_f0(glm::vec3 f0) {
  double distance = 0.0;
  const F0Reference& entry = nearest_f0_reference(f0, &distance);
  const std::string text = "F0 " + format_rgb(f0);
  if (distance <= kSameAsEntry) return text + " is " + entry.name;
  if (entry.low == entry.high) return text + " is nearest to " + entry.name + " " + format_rgb(entry.low, 3);
  return text + " is nearest to " + entry.name + " (" + format_rgb(entry.low, 3) + "-" + format_rgb(entry.high, 3) +
         ")";
}

}  // namespace gltf_pbr
