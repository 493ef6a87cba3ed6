// Environment maps, prefiltering and SH irradiance (see environment.hpp). No file access here:
// preview/bake_tables.cpp compiles this file alone to bake the built-in sky at build time.
#include "preview/environment.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "core/brdf.hpp"
#include "core/parallel.hpp"
#include "core/split_sum.hpp"
#include "preview/fast_math.hpp"

namespace gltf_pbr::preview {
namespace {

constexpr int kBaseWidth = 256, kBaseHeight = 128;
constexpr int kSpecularLevels = 7;
constexpr int kPrefilterSamples = 96;

// Area-averaging resample to width x height (box filter over each target texel's footprint).
EquirectMap resample(const EquirectMap& source, int width, int height) {
  EquirectMap out{width, height, std::vector<glm::vec3>(static_cast<size_t>(width) * static_cast<size_t>(height))};
  const int steps_x = std::max(1, source.width / width), steps_y = std::max(1, source.height / height);
  parallel_dynamic(height, [&](std::int64_t y) {
    for (int x = 0; x < width; ++x) {
      glm::vec3 sum(0.0f);
      for (int j = 0; j < steps_y; ++j)
        for (int i = 0; i < steps_x; ++i) {
          const float u = (static_cast<float>(x) + (static_cast<float>(i) + 0.5f) / static_cast<float>(steps_x)) /
                          static_cast<float>(width);
          const float v = (static_cast<float>(y) + (static_cast<float>(j) + 0.5f) / static_cast<float>(steps_y)) /
                          static_cast<float>(height);
          sum += source.sample(direction_of(u, v));
        }
      out.at(x, static_cast<int>(y)) = sum / static_cast<float>(steps_x * steps_y);
    }
  });
  return out;
}

EquirectMap half_size(const EquirectMap& m) {
  EquirectMap out{std::max(1, m.width / 2), std::max(1, m.height / 2), {}};
  out.texels.resize(static_cast<size_t>(out.width) * static_cast<size_t>(out.height));
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const int x0 = std::min(2 * x, m.width - 1), x1 = std::min(2 * x + 1, m.width - 1);
      const int y0 = std::min(2 * y, m.height - 1), y1 = std::min(2 * y + 1, m.height - 1);
      out.at(x, y) = (m.at(x0, y0) + m.at(x1, y0) + m.at(x0, y1) + m.at(x1, y1)) * 0.25f;
    }
  return out;
}

void orthonormal_basis(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
  // Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
}

// Prefiltered radiance for `roughness` with N = V = R (Karis 2013) and filtered importance
// sampling: each sample reads the mip whose texel matches its solid angle (Colbert & Krivanek
// 2007, "GPU-Based Importance Sampling", GPU Gems 3 ch. 20, eq. 13).
EquirectMap prefilter(const std::vector<EquirectMap>& pyramid, float roughness, int width, int height) {
  EquirectMap out{width, height, std::vector<glm::vec3>(static_cast<size_t>(width) * static_cast<size_t>(height))};
  const float alpha = alpha_from_roughness(roughness);
  const float texel_solid_angle = 4.0f * kPi / static_cast<float>(pyramid[0].width * pyramid[0].height);
  auto sample_lod = [&](glm::vec3 d, float lod) {
    lod = std::clamp(lod, 0.0f, static_cast<float>(pyramid.size() - 1));
    const int l0 = static_cast<int>(lod);
    const int l1 = std::min(l0 + 1, static_cast<int>(pyramid.size()) - 1);
    const float t = lod - static_cast<float>(l0);
    return glm::mix(pyramid[static_cast<size_t>(l0)].sample(d), pyramid[static_cast<size_t>(l1)].sample(d), t);
  };
  parallel_dynamic(height, [&](std::int64_t y) {
    for (int x = 0; x < width; ++x) {
      const glm::vec3 n = direction_of((static_cast<float>(x) + 0.5f) / static_cast<float>(width),
                                       (static_cast<float>(y) + 0.5f) / static_cast<float>(height));
      glm::vec3 t, b;
      orthonormal_basis(n, t, b);
      glm::vec3 sum(0.0f);
      float weight = 0.0f;
      for (int i = 0; i < kPrefilterSamples; ++i) {
        const glm::vec3 h_local =
            importance_sample_ggx(hammersley(static_cast<std::uint32_t>(i), kPrefilterSamples), alpha);
        const glm::vec3 h = t * h_local.x + b * h_local.y + n * h_local.z;
        const float n_dot_h = h_local.z;
        const glm::vec3 l = 2.0f * n_dot_h * h - n;
        const float n_dot_l = glm::dot(n, l);
        if (n_dot_l <= 0.0f) continue;
        // pdf(L) = D(h) (N.H) / (4 V.H), and V.H = N.H here.
        const float pdf = distribution_ggx(n_dot_h, alpha) / 4.0f;
        const float sample_solid_angle = 1.0f / (static_cast<float>(kPrefilterSamples) * pdf + 1e-6f);
        const float lod = 0.5f * std::log2(sample_solid_angle / texel_solid_angle) + 1.0f;
        sum += sample_lod(l, lod) * n_dot_l;
        weight += n_dot_l;
      }
      out.at(x, static_cast<int>(y)) = weight > 0.0f ? sum / weight : glm::vec3(0.0f);
    }
  });
  return out;
}

glm::vec3 procedural_sky(glm::vec3 d, glm::vec3 sun_direction) {
  const glm::vec3 zenith(0.16f, 0.30f, 0.62f), horizon(0.80f, 0.82f, 0.88f), ground(0.20f, 0.18f, 0.16f);
  glm::vec3 sky;
  if (d.y >= 0.0f) {
    const float t = std::pow(1.0f - d.y, 3.0f);
    sky = glm::mix(zenith, horizon, t);
  } else {
    const float t = std::min(1.0f, -d.y / 0.08f);  // short blend below the horizon
    sky = glm::mix(horizon * 0.6f, ground, t);
  }
  const float glow = std::max(0.0f, glm::dot(d, sun_direction));
  return sky + glm::vec3(1.0f, 0.9f, 0.75f) * (0.6f * std::pow(glow, 24.0f));
}

}  // namespace

glm::vec3 default_sun_direction() { return glm::normalize(glm::vec3(-0.45f, 0.75f, 0.55f)); }

EquirectMap default_sky() {
  const glm::vec3 sun = default_sun_direction();
  EquirectMap sky{512, 256, {}};
  sky.texels.resize(512 * 256);
  for (int y = 0; y < sky.height; ++y)
    for (int x = 0; x < sky.width; ++x)
      sky.at(x, y) = procedural_sky(direction_of((x + 0.5f) / sky.width, (y + 0.5f) / sky.height), sun);
  return sky;
}

glm::vec3 direction_of(float u, float v) {
  const float phi = (u - 0.5f) * 2.0f * kPi, theta = v * kPi;
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

glm::vec3 Environment::prefiltered_radiance(glm::vec3 direction, float roughness) const {
  return prefiltered_radiance_uv(equirect_uv(direction), roughness);
}

Environment build_environment(const EquirectMap& radiance) {
  Environment env;
  std::vector<EquirectMap> pyramid{resample(radiance, kBaseWidth, kBaseHeight)};
  while (pyramid.back().width > 4) pyramid.push_back(half_size(pyramid.back()));
  env.specular_levels.push_back(pyramid[0]);
  for (int level = 1; level < kSpecularLevels; ++level) {
    const int width = std::max(32, kBaseWidth >> level);
    env.specular_levels.push_back(
        prefilter(pyramid, static_cast<float>(level) / (kSpecularLevels - 1), width, width / 2));
  }
  // Project radiance on SH (solid angle of an equirect texel: (2 pi / W) (pi / H) sin theta), then
  // convolve with the clamped cosine: A0 = pi, A1 = 2 pi / 3, A2 = pi / 4 (R&H 2001, eq. 8).
  const EquirectMap& base = pyramid[0];
  std::array<glm::dvec3, 9> coefficients{};
  for (int y = 0; y < base.height; ++y) {
    const float v = (static_cast<float>(y) + 0.5f) / static_cast<float>(base.height);
    const double solid_angle = (2.0 * kPi / base.width) * (kPi / base.height) * std::sin(v * kPi);
    for (int x = 0; x < base.width; ++x) {
      const glm::vec3 d = direction_of((static_cast<float>(x) + 0.5f) / static_cast<float>(base.width), v);
      const auto basis = sh_basis(d);
      for (size_t i = 0; i < 9; ++i) coefficients[i] += glm::dvec3(base.at(x, y)) * (basis[i] * solid_angle);
    }
  }
  const float band[9] = {kPi, 2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4, kPi / 4, kPi / 4, kPi / 4, kPi / 4};
  for (size_t i = 0; i < 9; ++i) env.irradiance_sh[i] = glm::vec3(coefficients[i]) * band[i];
  return env;
}

Environment uniform_environment(glm::vec3 radiance) {
  EquirectMap constant{8, 4, std::vector<glm::vec3>(32, radiance)};
  return build_environment(constant);
}

}  // namespace gltf_pbr::preview
