// Image-based light by split sum (Karis 2013, "Real Shading in Unreal Engine 4", section
// "Image Based Lighting"): a radiance map prefiltered for GGX at several roughnesses, a DFG
// lookup table, and spherical-harmonic irradiance for the diffuse lobe (Ramamoorthi & Hanrahan
// 2001, "An Efficient Representation for Irradiance Environment Maps").
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <glm/common.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "core/split_sum.hpp"  // dfg_lookup, which the lighting reads beside the maps
#include "preview/fast_math.hpp"

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

// The per-pixel look-ups, inline: the lighting pass makes several a pixel.
inline glm::vec2 equirect_uv(glm::vec3 d) {
  const float u = 0.5f + fast_atan2(d.x, -d.z) / (2.0f * kPi);
  const float v = fast_acos(d.y) / kPi;
  return {u, v};
}

// Real SH up to l = 2 (Ramamoorthi & Hanrahan 2001, eq. 3 constants) of a unit direction, for a
// float or for SIMD lanes of them (preview/lighting_lanes.cpp).
template <typename Scalar>
[[gnu::always_inline]] inline std::array<Scalar, 9> sh_basis(Scalar x, Scalar y, Scalar z) {
  return {Scalar{} + 0.282095f,
          0.488603f * y,
          0.488603f * z,
          0.488603f * x,
          1.092548f * x * y,
          1.092548f * y * z,
          0.315392f * (3.0f * z * z - 1.0f),
          1.092548f * x * z,
          0.546274f * (x * x - y * y)};
}
inline std::array<float, 9> sh_basis(glm::vec3 d) { return sh_basis(d.x, d.y, d.z); }

inline glm::vec3 EquirectMap::sample(glm::vec3 d) const { return sample_uv(equirect_uv(d)); }

inline glm::vec3 EquirectMap::sample_uv(glm::vec2 uv) const {
  const float fx = uv.x * static_cast<float>(width) - 0.5f, fy = uv.y * static_cast<float>(height) - 0.5f;
  const float x0f = floor_fast(fx), y0f = floor_fast(fy);
  const float tx = fx - x0f, ty = fy - y0f;
  const int x0 = std::clamp(static_cast<int>(x0f), -1, width - 1), y0 = static_cast<int>(y0f);
  auto wrap_x = [&](int x) { return x < 0 ? x + width : (x >= width ? x - width : x); };
  auto clamp_y = [&](int y) { return std::clamp(y, 0, height - 1); };
  const glm::vec3 a = glm::mix(at(wrap_x(x0), clamp_y(y0)), at(wrap_x(x0 + 1), clamp_y(y0)), tx);
  const glm::vec3 b = glm::mix(at(wrap_x(x0), clamp_y(y0 + 1)), at(wrap_x(x0 + 1), clamp_y(y0 + 1)), tx);
  return glm::mix(a, b, ty);
}

inline glm::vec3 Environment::prefiltered_radiance_uv(glm::vec2 uv, float roughness) const {
  const float level = std::clamp(roughness, 0.0f, 1.0f) * static_cast<float>(specular_levels.size() - 1);
  const int l0 = static_cast<int>(level);
  const int l1 = std::min(l0 + 1, static_cast<int>(specular_levels.size()) - 1);
  const float t = level - static_cast<float>(l0);
  const glm::vec3 a = specular_levels[static_cast<size_t>(l0)].sample_uv(uv);
  return t > 0.0f ? glm::mix(a, specular_levels[static_cast<size_t>(l1)].sample_uv(uv), t) : a;
}

inline glm::vec3 Environment::irradiance(glm::vec3 n) const {
  const auto basis = sh_basis(n);
  glm::vec3 e(0.0f);
  for (size_t i = 0; i < 9; ++i) e += irradiance_sh[i] * basis[i];
  return glm::max(e, glm::vec3(0.0f));  // order-2 SH rings below zero behind bright lights
}

inline glm::vec3 Environment::background(glm::vec3 direction) const { return specular_levels[1].sample(direction); }

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
