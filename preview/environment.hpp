// Image-based light by split sum (Karis 2013, "Real Shading in Unreal Engine 4", section
// "Image Based Lighting"): a radiance map prefiltered for GGX at several roughnesses, a DFG
// lookup table, and spherical-harmonic irradiance for the diffuse lobe (Ramamoorthi & Hanrahan
// 2001, "An Efficient Representation for Irradiance Environment Maps").
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "core/split_sum.hpp"  // dfg_lookup, which the lighting reads beside the maps

namespace gltf_pbr::preview {

// Equirectangular (latitude-longitude) radiance, +Y up; u = 0.5 + atan2(x, -z) / 2 pi, v = acos(y) / pi.
struct EquirectMap {
  int width = 0, height = 0;
  std::vector<glm::vec3> texels;
  glm::vec3 sample(glm::vec3 direction) const;  // bilinear
  glm::vec3 sample_uv(glm::vec2 uv) const;
  glm::vec3& at(int x, int y) {
    return texels[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
  }
  const glm::vec3& at(int x, int y) const {
    return texels[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
  }
};
glm::vec3 direction_of(float u, float v);  // inverse of the mapping above
glm::vec2 equirect_uv(glm::vec3 direction);

struct Environment {
  std::vector<EquirectMap> specular_levels;   // level k prefiltered for roughness k / (levels - 1)
  std::array<glm::vec3, 9> irradiance_sh{};   // order-2 SH of irradiance E(n), cosine lobe applied
  glm::vec3 sun_direction{0.0f, 1.0f, 0.0f};  // towards the sun
  glm::vec3 sun_irradiance{0.0f};             // W/m^2-like units at normal incidence
  glm::vec3 prefiltered_radiance(glm::vec3 direction, float roughness) const;
  glm::vec3 prefiltered_radiance_uv(glm::vec2 equirect_uv, float roughness) const;
  glm::vec3 irradiance(glm::vec3 normal) const;
  glm::vec3 background(glm::vec3 direction) const;  // slightly blurred, behind the model
};

// Builds the prefiltered levels and SH from radiance (any size; resampled to 256 x 128).
Environment build_environment(const EquirectMap& radiance);

// The built-in default: a procedural sky (zenith blue to a bright horizon) over a grey-brown
// ground, plus an analytic sun from the upper front-left. build_environment(default_sky()) with
// the sun, baked into the build by preview/bake_tables.cpp: no process computes it.
const Environment& default_environment();
EquirectMap default_sky();          // the sky's radiance (sun glow included), 512 x 256
glm::vec3 default_sun_direction();  // towards the sun
inline glm::vec3 default_sun_irradiance() { return {2.4f, 2.25f, 2.0f}; }

// A constant-radiance environment with no sun: the white furnace.
Environment uniform_environment(glm::vec3 radiance);

// Reads a Radiance .hdr (RGBE, Ward 1991; run-length encoded or flat) itself, or anything else
// through core/image.hpp (OpenImageIO: .exr where its reader recognises the bytes). Throws
// std::runtime_error naming the file. (preview/environment_file.cpp)
Environment load_environment(const std::filesystem::path& path);
EquirectMap read_radiance_hdr(const std::vector<std::uint8_t>& bytes, const std::string& name);

}  // namespace gltf_pbr::preview
