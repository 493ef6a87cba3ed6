// The lighting pass eight pixels at a time (see lighting_lanes.hpp). Every function below is the
// lane form of a scalar one named beside it, with the same operations in the same order, so that
// each lane rounds as the scalar reference does: light_both_reference in lighting.cpp, which
// tests/preview/lighting_lanes_test.cpp compares byte for byte. Built with -ffp-contract=off and
// -fno-math-errno (preview/CMakeLists.txt): the AVX2 clone must not fuse a multiply-add the
// reference rounds twice, and a lane's square root must not call libm to set errno.
#include "preview/lighting_lanes.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/color.hpp"
#include "core/lanes.hpp"
#include "core/split_sum.hpp"

namespace gltf_pbr::preview {
namespace {

using lanes::Floats;
using lanes::Ints;
using lanes::kLanes;
using lanes::Mask;
using lanes::select;
using lanes::splat;
using lanes::square_root;
using lanes::to_floats;
using lanes::truncate;

// std::min / std::max / std::clamp / glm::min / glm::max as their definitions compare, so that a
// NaN lane takes the branch the scalar code takes.
GLTF_PBR_INLINE Floats std_max(Floats a, Floats b) { return select(a < b, b, a); }
GLTF_PBR_INLINE Floats std_min(Floats a, Floats b) { return select(b < a, b, a); }
GLTF_PBR_INLINE Floats std_clamp(Floats v, float lo, float hi) {
  return select(v < lo, splat(lo), select(splat(hi) < v, splat(hi), v));
}
GLTF_PBR_INLINE Ints int_clamp(Ints v, int lo, int hi) { return v < lo ? Ints{} + lo : (v > hi ? Ints{} + hi : v); }
GLTF_PBR_INLINE Mask finite(Floats x) { return lanes::abs(x) <= std::numeric_limits<float>::max(); }
GLTF_PBR_INLINE Floats mix(Floats a, Floats b, Floats t) { return a * (1.0f - t) + b * t; }  // glm::mix

struct Vec3 {
  Floats x, y, z;
};
GLTF_PBR_INLINE Vec3 splat3(glm::vec3 v) { return {splat(v.x), splat(v.y), splat(v.z)}; }
GLTF_PBR_INLINE Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
GLTF_PBR_INLINE Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
GLTF_PBR_INLINE Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
GLTF_PBR_INLINE Vec3 operator*(Vec3 a, Floats s) { return {a.x * s, a.y * s, a.z * s}; }
GLTF_PBR_INLINE Vec3 operator/(Vec3 a, float s) { return {a.x / s, a.y / s, a.z / s}; }
GLTF_PBR_INLINE Vec3 select3(Mask m, Vec3 a, Vec3 b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
GLTF_PBR_INLINE Vec3 mix3(Vec3 a, Vec3 b, Floats t) { return {mix(a.x, b.x, t), mix(a.y, b.y, t), mix(a.z, b.z, t)}; }
GLTF_PBR_INLINE Floats dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
GLTF_PBR_INLINE Vec3 normalize(Vec3 v) { return v * (1.0f / square_root(dot(v, v))); }  // glm::normalize

// preview/fast_math.hpp
GLTF_PBR_INLINE Floats floor_fast(Floats x) {
  const Mask fractional = lanes::abs(x) < 8388608.0f;
  const Floats truncated = to_floats(truncate(select(fractional, x, Floats{})));  // no lane out of int range
  const Floats floored = select(truncated > x, truncated - 1.0f, truncated);
  return select(fractional, floored, x);
}
GLTF_PBR_INLINE Floats fast_atan2(Floats y, Floats x) {
  const Floats ax = lanes::abs(x), ay = lanes::abs(y);
  const Floats largest = std_max(ax, ay);
  const Floats a = std_min(ax, ay) / largest, s = a * a;
  Floats r = ((-0.0464964749f * s + 0.15931422f) * s - 0.327622764f) * s * a + a;
  r = select(ay > ax, 0.5f * kPi - r, r);
  r = select(x < 0.0f, kPi - r, r);
  r = select(y < 0.0f, -r, r);
  return select(largest > 0.0f, r, Floats{});
}
GLTF_PBR_INLINE Floats fast_acos(Floats x) {
  const Floats ax = std_min(lanes::abs(x), splat(1.0f));
  const Floats r = square_root(1.0f - ax) * (((-0.0187293f * ax + 0.0742610f) * ax - 0.2121144f) * ax + 1.5707288f);
  return select(x < 0.0f, kPi - r, r);
}

// preview/environment.hpp
struct Uv {
  Floats u, v;
};
GLTF_PBR_INLINE Uv equirect_uv(Vec3 d) { return {0.5f + fast_atan2(d.x, -d.z) / (2.0f * kPi), fast_acos(d.y) / kPi}; }

// EquirectMap::sample_uv of the level each lane names.
GLTF_PBR_INLINE Vec3 sample_levels(const Environment& env, Ints level, Uv uv) {
  Floats width, height;
  for (int l = 0; l < kLanes; ++l) {
    const EquirectMap& map = env.specular_levels[static_cast<size_t>(level[l])];
    width[l] = static_cast<float>(map.width), height[l] = static_cast<float>(map.height);
  }
  const Floats fx = uv.u * width - 0.5f, fy = uv.v * height - 0.5f;
  const Floats x0f = floor_fast(fx), y0f = floor_fast(fy);
  const Floats tx = fx - x0f, ty = fy - y0f;
  const Ints widths = truncate(width), heights = truncate(height);
  const Ints x0 = int_clamp(truncate(x0f), -1, 0x7fffffff);
  Vec3 taps[4];
  for (int l = 0; l < kLanes; ++l) {
    const EquirectMap& map = env.specular_levels[static_cast<size_t>(level[l])];
    const int w = widths[l], h = heights[l];
    const int first = std::min(x0[l], w - 1), y = truncate(y0f)[l];
    auto wrap_x = [&](int x) { return x < 0 ? x + w : (x >= w ? x - w : x); };
    auto clamp_y = [&](int row) { return std::clamp(row, 0, h - 1); };
    const glm::vec3* texel[4] = {&map.at(wrap_x(first), clamp_y(y)), &map.at(wrap_x(first + 1), clamp_y(y)),
                                 &map.at(wrap_x(first), clamp_y(y + 1)), &map.at(wrap_x(first + 1), clamp_y(y + 1))};
    for (int k = 0; k < 4; ++k) taps[k].x[l] = texel[k]->x, taps[k].y[l] = texel[k]->y, taps[k].z[l] = texel[k]->z;
  }
  return mix3(mix3(taps[0], taps[1], tx), mix3(taps[2], taps[3], tx), ty);
}

// Environment::prefiltered_radiance_uv
GLTF_PBR_INLINE Vec3 prefiltered_radiance(const Environment& env, Uv uv, Floats roughness) {
  const int last = static_cast<int>(env.specular_levels.size()) - 1;
  const Floats level = std_clamp(roughness, 0.0f, 1.0f) * static_cast<float>(last);
  const Ints l0 = truncate(level);
  const Floats t = level - to_floats(l0);
  const Vec3 a = sample_levels(env, l0, uv);
  const Mask blend = t > 0.0f;
  if (!lanes::any(blend)) return a;
  const Ints l1 = l0 + 1 > last ? Ints{} + last : l0 + 1;
  return select3(blend, mix3(a, sample_levels(env, l1, uv), t), a);
}

// Environment::irradiance
GLTF_PBR_INLINE Vec3 irradiance(const Environment& env, Vec3 d) {
  const auto basis = sh_basis(d.x, d.y, d.z);
  Vec3 e{Floats{}, Floats{}, Floats{}};
  for (size_t i = 0; i < 9; ++i) e = e + splat3(env.irradiance_sh[i]) * basis[i];
  return {std_max(e.x, Floats{}), std_max(e.y, Floats{}), std_max(e.z, Floats{})};
}

// dfg_lookup (core/dfg_table.cpp), its `unit` first
GLTF_PBR_INLINE Floats unit(Floats x) { return select(x > 0.0f, std_min(x, splat(1.0f)), Floats{}); }
struct Dfg {
  Floats scale, bias;
};
GLTF_PBR_INLINE Dfg dfg_lookup(Floats n_dot_v, Floats roughness) {
  const Floats fx = square_root(unit(n_dot_v)) * static_cast<float>(kDfgTableSize) - 0.5f;
  const Floats fy = unit(roughness) * static_cast<float>(kDfgTableSize) - 0.5f;
  const Ints x0 = int_clamp(truncate(fx + 1.0f) - 1, 0, kDfgTableSize - 1),
             y0 = int_clamp(truncate(fy + 1.0f) - 1, 0, kDfgTableSize - 1);
  const Ints x1 = x0 + 1 > kDfgTableSize - 1 ? x0 : x0 + 1, y1 = y0 + 1 > kDfgTableSize - 1 ? y0 : y0 + 1;
  const Floats tx = std_clamp(fx - to_floats(x0), 0.0f, 1.0f), ty = std_clamp(fy - to_floats(y0), 0.0f, 1.0f);
  Floats cells[4][2];
  const Ints columns[4] = {x0, x1, x0, x1}, rows[4] = {y0, y0, y1, y1};
  for (int k = 0; k < 4; ++k)
    for (int l = 0; l < kLanes; ++l) {
      const float* cell = baked::kDfgTable + 2 * (rows[k][l] * kDfgTableSize + columns[k][l]);
      cells[k][0][l] = cell[0], cells[k][1][l] = cell[1];
    }
  return {mix(mix(cells[0][0], cells[1][0], tx), mix(cells[2][0], cells[3][0], tx), ty),
          mix(mix(cells[0][1], cells[1][1], tx), mix(cells[2][1], cells[3][1], tx), ty)};
}

// SurfaceLobes (core/brdf.hpp)
struct Lobes {
  Vec3 diffuse_color, f0;
  Floats alpha;
  Vec3 diffuse_fresnel_f0;
  Floats diffuse_fresnel_scale;
};
GLTF_PBR_INLINE Floats alpha_from_roughness(Floats roughness) {
  const Floats r = select(roughness < 0.0f, Floats{}, select(roughness > 1.0f, splat(1.0f), roughness));
  return select(r * r < kMinAlpha, splat(kMinAlpha), r * r);
}
GLTF_PBR_INLINE Lobes metal_rough_lobes(Vec3 base, Floats metalness, Floats roughness) {
  const Vec3 dielectric = splat3(glm::vec3(kDielectricF0));
  return {base * (1.0f - metalness), mix3(dielectric, base, metalness), alpha_from_roughness(roughness), dielectric,
          splat(1.0f)};
}
GLTF_PBR_INLINE Lobes spec_gloss_lobes(Vec3 diffuse, Vec3 specular, Floats glossiness, bool reading_b) {
  const Floats max_specular = std_max(specular.x, std_max(specular.y, specular.z));
  return {diffuse * std_max(Floats{}, 1.0f - max_specular), specular, alpha_from_roughness(1.0f - glossiness),
          reading_b ? specular : splat3(glm::vec3(kDielectricF0)),
          splat(reading_b ? 1.0f : 1.0f / (1.0f - kDielectricF0))};
}

// fresnel_schlick's weight (1 - V.H)^5 and the lobe it gives an F0
GLTF_PBR_INLINE Floats schlick_weight(Floats v_dot_h) {
  const Floats c = 1.0f - select(v_dot_h < 0.0f, Floats{}, select(v_dot_h > 1.0f, splat(1.0f), v_dot_h));
  const Floats c2 = c * c;
  return c2 * c2 * c;
}
GLTF_PBR_INLINE Vec3 fresnel(Vec3 f0, Floats weight) {
  return {f0.x + (1.0f - f0.x) * weight, f0.y + (1.0f - f0.y) * weight, f0.z + (1.0f - f0.z) * weight};
}

// shade_direct (core/brdf.hpp)
GLTF_PBR_INLINE Vec3 shade_direct(const Lobes& s, Vec3 n, Vec3 v, glm::vec3 light, glm::vec3 light_irradiance,
                                  SpecularLobe lobe) {
  const Vec3 to_light = splat3(light);
  const Floats n_dot_l = dot(n, to_light);
  const Floats n_dot_v = std_max(dot(n, v), splat(1e-4f));
  const Vec3 h = normalize(v + to_light);
  const Floats n_dot_h = std_max(dot(n, h), Floats{});
  const Floats weight = schlick_weight(dot(v, h));
  const Vec3 f = fresnel(s.f0, weight);
  Floats specular_lobe;
  const Floats a2 = s.alpha * s.alpha;
  if (lobe == SpecularLobe::Ggx) {
    const Floats d = n_dot_h * n_dot_h * (a2 - 1.0f) + 1.0f;
    const Floats distribution = a2 / (kPi * d * d);
    const Floats lambda_v = n_dot_l * square_root(n_dot_v * n_dot_v * (1.0f - a2) + a2);
    const Floats lambda_l = n_dot_v * square_root(n_dot_l * n_dot_l * (1.0f - a2) + a2);
    const Floats sum = lambda_v + lambda_l;
    specular_lobe = distribution * select(sum > 0.0f, 0.5f / sum, Floats{});
  } else {
    for (int l = 0; l < kLanes; ++l) specular_lobe[l] = normalized_blinn_phong(n_dot_h[l], s.alpha[l]);
  }
  const Vec3 diffuse_weight =
      (splat3(glm::vec3(1.0f)) - fresnel(s.diffuse_fresnel_f0, weight)) * s.diffuse_fresnel_scale;
  const Vec3 radiance =
      ((diffuse_weight * s.diffuse_color) / kPi + f * specular_lobe) * splat3(light_irradiance) * n_dot_l;
  return select3(n_dot_l <= 0.0f, Vec3{Floats{}, Floats{}, Floats{}}, radiance);
}

// PixelGeometry and prepare (lighting.cpp)
struct Geometry {
  Vec3 n, v;
  Floats n_dot_v;
  Uv reflected_uv;
  Vec3 irradiance;
};
GLTF_PBR_INLINE Geometry prepare(Vec3 n, Vec3 v, const Environment& env) {
  Floats n_dot_v = dot(n, v);
  const Mask bend = n_dot_v < 1e-3f;
  if (lanes::any(bend)) {
    const Vec3 bent = normalize(n + v * (1e-3f - n_dot_v));
    n = select3(bend, bent, n);
    n_dot_v = select(bend, std_max(dot(bent, v), splat(1e-4f)), n_dot_v);
  }
  const Floats twice = 2.0f * n_dot_v;
  const Vec3 reflected{twice * n.x - v.x, twice * n.y - v.y, twice * n.z - v.z};
  return {n, v, n_dot_v, equirect_uv(reflected), irradiance(env, n)};
}

// shade_prepared (lighting.cpp)
GLTF_PBR_INLINE Vec3 shade(const Lobes& lobes, Floats roughness, const Geometry& g, Floats occlusion, Vec3 emissive,
                           const Environment& env, const LightingOptions& options) {
  Vec3 color{Floats{}, Floats{}, Floats{}};
  if (options.sun && env.sun_irradiance != glm::vec3(0.0f))
    color = color + shade_direct(lobes, g.n, g.v, env.sun_direction, env.sun_irradiance, options.lobe);
  const Dfg dfg = dfg_lookup(g.n_dot_v, roughness);
  const Vec3 specular =
      prefiltered_radiance(env, g.reflected_uv, roughness) *
      Vec3{lobes.f0.x * dfg.scale + dfg.bias, lobes.f0.y * dfg.scale + dfg.bias, lobes.f0.z * dfg.scale + dfg.bias};
  const Vec3 diffuse_loss{1.0f - (lobes.diffuse_fresnel_f0.x * dfg.scale + dfg.bias),
                          1.0f - (lobes.diffuse_fresnel_f0.y * dfg.scale + dfg.bias),
                          1.0f - (lobes.diffuse_fresnel_f0.z * dfg.scale + dfg.bias)};
  const Vec3 diffuse = (lobes.diffuse_color * g.irradiance) / kPi * lobes.diffuse_fresnel_scale * diffuse_loss;
  color = color + ((diffuse + specular) * occlusion + emissive);
  return select3(finite(color.x + color.y + color.z), color, Vec3{Floats{}, Floats{}, Floats{}});
}

// aces (lighting.cpp) of one channel
GLTF_PBR_INLINE Floats aces(Floats x) {
  return std_clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

// tone_map_pixel (lighting.cpp) up to the sRGB encoding
GLTF_PBR_INLINE Vec3 tone_map(Vec3 radiance, const LightingOptions& options) {
  Vec3 c = radiance * splat(options.exposure);
  c = {std_max(c.x, Floats{}), std_max(c.y, Floats{}), std_max(c.z, Floats{})};
  if (options.tone_map == ToneMap::KhronosPbrNeutral) {
    constexpr float kStartCompression = 0.8f - 0.04f, kDesaturation = 0.15f;
    const Floats x = std_min(c.x, std_min(c.y, c.z));
    const Floats offset = select(x < 0.08f, x - 6.25f * x * x, splat(0.04f));
    c = c - Vec3{offset, offset, offset};
    const Floats peak = std_max(c.x, std_max(c.y, c.z));
    constexpr float d = 1.0f - kStartCompression;
    const Floats new_peak = 1.0f - d * d / (peak + d - kStartCompression);
    const Vec3 compressed = c * (new_peak / peak);
    const Floats g = 1.0f - 1.0f / (kDesaturation * (peak - new_peak) + 1.0f);
    return select3(peak < kStartCompression, c, mix3(compressed, Vec3{new_peak, new_peak, new_peak}, g));
  }
  if (options.tone_map == ToneMap::Aces) {
    return {aces(c.x), aces(c.y), aces(c.z)};
  }
  return {std_clamp(c.x, 0.0f, 1.0f), std_clamp(c.y, 0.0f, 1.0f), std_clamp(c.z, 0.0f, 1.0f)};
}

// encode_srgb8 (gbuffer.hpp): the step in lanes, the tables a lane at a time.
GLTF_PBR_INLINE Ints encode_srgb8(Floats linear) {
  const Floats clamped = select(linear > 0.0f, select(linear < 1.0f, linear, splat(1.0f)), Floats{});
  const Ints step = truncate(clamped * 65535.0f + 0.5f);
  Ints code;
  for (int l = 0; l < kLanes; ++l) {
    const auto s = static_cast<std::uint32_t>(step[l]);
    const std::uint32_t bucket = kSrgbEncode.bucket_code[s >> 4];
    code[l] = static_cast<int>(bucket + (s >= kSrgbEncode.first_step[bucket + 1] ? 1u : 0u));
  }
  return code;
}

GLTF_PBR_INLINE void store_rgb8(Vec3 mapped, std::uint8_t* out, int count) {
  const Ints r = encode_srgb8(mapped.x), g = encode_srgb8(mapped.y), b = encode_srgb8(mapped.z);
  for (int l = 0; l < count; ++l, out += 3)
    out[0] = static_cast<std::uint8_t>(r[l]), out[1] = static_cast<std::uint8_t>(g[l]),
    out[2] = static_cast<std::uint8_t>(b[l]);
}

GLTF_PBR_INLINE void store_hdr(Vec3 radiance, glm::vec3* out, int count) {
  for (int l = 0; l < count; ++l) out[l] = {radiance.x[l], radiance.y[l], radiance.z[l]};
}

// glm::normalize(octahedral 12 + 12) (unpack_octahedral_12_12, gbuffer.cpp)
GLTF_PBR_INLINE Vec3 unpack_octahedral(Ints bits) {
  const Floats ex = to_floats(bits & 4095) / 4095.0f * 2.0f - 1.0f;
  const Floats ey = to_floats((bits >> 12) & 4095) / 4095.0f * 2.0f - 1.0f;
  const Floats ez = 1.0f - lanes::abs(ex) - lanes::abs(ey);
  const Floats sign_x = select(ex >= 0.0f, splat(1.0f), splat(-1.0f));
  const Floats sign_y = select(ey >= 0.0f, splat(1.0f), splat(-1.0f));
  const Mask folded = ez < 0.0f;
  const Vec3 n{select(folded, (1.0f - lanes::abs(ey)) * sign_x, ex),
               select(folded, (1.0f - lanes::abs(ex)) * sign_y, ey), ez};
  return normalize(n);
}

// Pixels x0 .. x0 + count - 1 (count <= 8) of row y. `lut`: srgb8_to_linear_table().
GLTF_PBR_INLINE void light_eight(const LightingPass& pass, const std::array<float, 256>& lut, std::int64_t y, int x0,
                                 int count) {
  const GBuffer& a = pass.gbuffers.after;
  const GBuffer& b = pass.gbuffers.before;
  const Environment& env = pass.env;
  const LightingOptions& options = pass.options;
  const size_t row = static_cast<size_t>(y) * static_cast<size_t>(a.width);
  const size_t first = row + static_cast<size_t>(x0);
  // Lanes past the row's end repeat its last pixel and are not stored.
  size_t index[kLanes];
  Floats depth;
  Floats px;
  for (int l = 0; l < kLanes; ++l) {
    const int x = x0 + std::min(l, count - 1);
    index[l] = row + static_cast<size_t>(x);
    depth[l] = a.depth[index[l]];
    px[l] = static_cast<float>(x) + 0.5f;
  }
  const Mask covered = finite(depth);
  const Floats py = splat(static_cast<float>(y) + 0.5f);
  const RayGenerator& rays = pass.rays;
  const Vec3 ray = normalize(rays.orthographic ? splat3(rays.forward)
                                               : splat3(rays.corner) + splat3(rays.right_per_pixel) * px +
                                                     splat3(rays.up_per_pixel) * py);
  Vec3 before_radiance{}, after_radiance{};
  if (lanes::any(covered)) {
    Ints normal_bits, roughness_code, gloss_code;
    Vec3 albedo, diffuse, specular, after_emissive{}, before_emissive{};
    Floats metalness, after_occlusion = splat(1.0f), before_occlusion = splat(1.0f);
    for (int l = 0; l < kLanes; ++l) {
      const size_t i = covered[l] ? index[l] : first;  // a background lane reads any texel, unused
      // read_before_material: where the "before" side drew nothing, its texel's defaults (the two
      // G-buffer producers write one depth to both sides, so this is for completeness).
      const bool before_covered = std::isfinite(b.depth[i]);
      const std::uint32_t bits = a.normal[i].bits;
      normal_bits[l] = static_cast<int>(bits & 0xFFFFFFu), roughness_code[l] = static_cast<int>(bits >> 24);
      gloss_code[l] = before_covered ? static_cast<int>(b.normal[i].bits >> 24) : 0;
      const AlbedoMetalness& am = a.albedo[i];
      albedo.x[l] = lut[am.albedo_srgb[0]], albedo.y[l] = lut[am.albedo_srgb[1]], albedo.z[l] = lut[am.albedo_srgb[2]];
      metalness[l] = static_cast<float>(am.metalness) / 255.0f;
      const DiffuseSpecular ds = before_covered ? b.diffspec[i] : DiffuseSpecular{};
      diffuse.x[l] = lut[ds.diffuse_srgb[0]], diffuse.y[l] = lut[ds.diffuse_srgb[1]],
      diffuse.z[l] = lut[ds.diffuse_srgb[2]];
      specular.x[l] = lut[ds.specular_srgb[0]], specular.y[l] = lut[ds.specular_srgb[1]],
      specular.z[l] = lut[ds.specular_srgb[2]];
      if (!a.emissive.empty()) {
        const glm::vec3 e = unpack_rgb9e5(a.emissive[i].rgb9e5);
        after_emissive.x[l] = e.x, after_emissive.y[l] = e.y, after_emissive.z[l] = e.z;
      }
      if (!b.emissive.empty() && before_covered) {
        const glm::vec3 e = unpack_rgb9e5(b.emissive[i].rgb9e5);
        before_emissive.x[l] = e.x, before_emissive.y[l] = e.y, before_emissive.z[l] = e.z;
      }
      if (!a.occlusion.empty()) after_occlusion[l] = static_cast<float>(a.occlusion[i]) / 255.0f;
      if (!b.occlusion.empty() && before_covered) before_occlusion[l] = static_cast<float>(b.occlusion[i]) / 255.0f;
    }
    const Vec3 v{-ray.x, -ray.y, -ray.z};
    const Geometry geometry = prepare(unpack_octahedral(normal_bits), v, env);
    const Floats roughness = to_floats(roughness_code) / 255.0f, gloss = to_floats(gloss_code) / 255.0f;
    after_radiance = shade(metal_rough_lobes(albedo, metalness, roughness), roughness, geometry, after_occlusion,
                           after_emissive, env, options);
    before_radiance = shade(spec_gloss_lobes(diffuse, specular, gloss, options.legacy_reading_b), 1.0f - gloss,
                            geometry, before_occlusion, before_emissive, env, options);
  }
  if (!lanes::all(covered)) {  // Environment::background: the same sky behind both sides
    const Vec3 sky = sample_levels(env, Ints{} + 1, equirect_uv(ray));
    after_radiance = select3(covered, after_radiance, sky);
    before_radiance = select3(covered, before_radiance, sky);
  }
  store_rgb8(tone_map(after_radiance, options), &pass.out.after[first * 3], count);
  if (lanes::any(covered))
    store_rgb8(tone_map(before_radiance, options), &pass.out.before[first * 3], count);
  else  // only sky: the same pixels on both sides, mapped once
    std::memcpy(&pass.out.before[first * 3], &pass.out.after[first * 3], static_cast<size_t>(count) * 3);
  for (int l = 0; l < count; ++l) pass.out.covered[first + static_cast<size_t>(l)] = covered[l] ? 1 : 0;
  if (pass.keep_radiance) {
    store_hdr(before_radiance, &pass.out.before_hdr.radiance[first], count);
    store_hdr(after_radiance, &pass.out.after_hdr.radiance[first], count);
    for (int l = 0; l < count; ++l)
      pass.out.before_hdr.covered[first + static_cast<size_t>(l)] =
          pass.out.after_hdr.covered[first + static_cast<size_t>(l)] = covered[l] ? 1 : 0;
  }
}

}  // namespace

GLTF_PBR_LANE_CLONES void light_row(const LightingPass& pass, std::int64_t y) {
  const std::array<float, 256>& lut = srgb8_to_linear_table();
  const int width = pass.gbuffers.after.width;
  for (int x = 0; x < width; x += kLanes) light_eight(pass, lut, y, x, std::min(kLanes, width - x));
}

}  // namespace gltf_pbr::preview
