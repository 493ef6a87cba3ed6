// DESIGN.md's reference F0 values (dielectric classes and Hoffman's measured metals) and the
// naming of an F0 by the entry it most resembles: "F0 (0.97, 0.96, 0.92) is Silver".
#pragma once
#include <glm/vec3.hpp>
#include <span>
#include <string>

namespace gltf_pbr {

struct F0Reference {
  const char* name;
  glm::vec3 low, high;  // equal for a measured metal; a range for a dielectric class
  bool metal;
};

// Dielectrics (DESIGN.md "physics", seed table) then metals (Hoffman, "Physics and Math of Shading").
std::span<const F0Reference> f0_references();

// The entry nearest to `f0`: CIEDE2000 to the nearest point of the entry's range.
const F0Reference& nearest_f0_reference(glm::vec3 f0, double* distance = nullptr);

// "F0 0.02 is water", "F0 (0.97, 0.96, 0.92) is Silver", or, when no entry is within ΔE2000 2,
// "F0 (0.80, 0.53, 0.00) is nearest to Gold (1.022, 0.782, 0.344)".
std::string describe_f0(glm::vec3 f0);

// "0.80" for an achromatic triple (all channels equal to 2 decimals), else "(0.80, 0.53, 0.00)".
std::string format_rgb(glm::vec3 value, int decimals = 2);
std::string format_number(double value, int decimals);

}  // namespace gltf_pbr
