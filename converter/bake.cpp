#include "converter/bake.hpp"

#include "core/parallel.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <thread>

#include "core/color.hpp"

namespace gltf_pbr {
namespace {

std::uint8_t quantize(float value) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f));
}

// The value of channel c (RGBA) of a texel: grey images repeat their one channel and a missing
// alpha reads as 1 (PNG and JPEG channel expansion). 8-bit sRGB goes through a table.
float channel(const Pixels& pixels, size_t texel, int c, bool srgb) {
  if (c == 3 && pixels.channels != 2 && pixels.channels != 4) return 1.0f;
  const int source = c == 3 ? pixels.channels - 1 : (pixels.channels >= 3 ? c : 0);
  const float value = pixels.values[texel * static_cast<size_t>(pixels.channels) + static_cast<size_t>(source)];
  if (!srgb) return value;
  return pixels.bits == 8 ? srgb8_to_linear(quantize(value)) : srgb_to_linear(value);
}

// The solve depends only on diffuse and specular (roughness is 1 - glossiness), and textures
// repeat those pairs a lot: a direct-mapped cache of recent solves, keyed by the exact input bits,
// skips most of the work without changing any result.
class SolveCache {
 public:
  explicit SolveCache(const SolverSettings& settings) : settings_(settings), entries_(kSize) {}
  glm::vec4 solve(const SpecGloss& legacy) {
    Key key;
    std::memcpy(key.bits, &legacy.diffuse, sizeof(float) * 3);
    std::memcpy(key.bits + 3, &legacy.specular, sizeof(float) * 3);
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the six words
    for (std::uint32_t word : key.bits) hash = (hash ^ word) * 1099511628211ull;
    Entry& entry = entries_[(hash ^ (hash >> 29)) & (kSize - 1)];
    if (entry.filled && std::memcmp(entry.key.bits, key.bits, sizeof key.bits) == 0) return entry.result;
    const MetalRough r = gltf_pbr::solve(legacy, settings_);
    entry = {key, glm::vec4(r.base, r.metalness), true};
    return entry.result;
  }

 private:
  static constexpr size_t kSize = 1u << 16;
  struct Key {
    std::uint32_t bits[6];
  };
  struct Entry {
    Key key;
    glm::vec4 result;
    bool filled = false;
  };
  const SolverSettings& settings_;
  std::vector<Entry> entries_;
};

}  // namespace

float srgb8_to_linear(std::uint8_t value) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[static_cast<size_t>(i)] = srgb_to_linear(static_cast<float>(i) / 255.0f);
    return t;
  }();
  return table[value];
}

BakedTexels bake(const BakeInputs& in, const SolverSettings& settings, size_t max_error_samples) {
  BakedTexels out;
  out.width = in.width;
  out.height = in.height;
  const size_t texels = static_cast<size_t>(in.width) * static_cast<size_t>(in.height);
  out.base_color.resize(texels * 4);
  out.metal_rough.resize(texels * 3);
  const size_t stride = max_error_samples == 0 ? 1 : std::max<size_t>(1, texels / max_error_samples);
  std::vector<ErrorAccumulator> rows_a(static_cast<size_t>(in.height)), rows_b(static_cast<size_t>(in.height));

  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  parallel_for(0, threads, [&](std::int64_t thread) {
   SolveCache cache(settings);
   for (std::int64_t y = in.height * thread / threads, last = in.height * (thread + 1) / threads; y < last; ++y) {
    for (size_t i = static_cast<size_t>(y) * static_cast<size_t>(in.width),
                end = i + static_cast<size_t>(in.width); i < end; ++i) {
      SpecGloss legacy;
      float alpha = in.diffuse_factor.a;
      legacy.diffuse = glm::vec3(in.diffuse_factor);
      if (in.diffuse) {
        for (int c = 0; c < 3; ++c) legacy.diffuse[c] *= channel(*in.diffuse, i, c, true);
        alpha *= channel(*in.diffuse, i, 3, false);
      }
      legacy.specular = in.specular_factor;
      legacy.glossiness = in.glossiness_factor;
      if (in.spec_gloss) {
        for (int c = 0; c < 3; ++c) legacy.specular[c] *= channel(*in.spec_gloss, i, c, true);
        legacy.glossiness *= channel(*in.spec_gloss, i, 3, false);
      }
      const glm::vec4 solved = cache.solve(legacy);
      const MetalRough core{glm::vec3(solved), solved.w, std::clamp(1.0f - legacy.glossiness, 0.0f, 1.0f)};
      for (int c = 0; c < 3; ++c) out.base_color[i * 4 + static_cast<size_t>(c)] = quantize(linear_to_srgb(core.base[c]));
      out.base_color[i * 4 + 3] = quantize(alpha);
      out.metal_rough[i * 3 + 0] = 0;
      out.metal_rough[i * 3 + 1] = quantize(core.roughness);
      out.metal_rough[i * 3 + 2] = quantize(core.metalness);
      if (i % stride == 0) {
        // The error of what is stored: the quantized texels, read back as a viewer reads them.
        MetalRough stored;
        for (int c = 0; c < 3; ++c) stored.base[c] = srgb8_to_linear(out.base_color[i * 4 + static_cast<size_t>(c)]);
        stored.metalness = static_cast<float>(out.metal_rough[i * 3 + 2]) / 255.0f;
        const Reflectance converted = core_reflectance(stored);
        rows_a[static_cast<size_t>(y)].add(legacy_reflectance(legacy, LegacyReading::A), converted);
        rows_b[static_cast<size_t>(y)].add(legacy_reflectance(legacy, LegacyReading::B), converted);
      }
    }
   }
  });
  for (size_t y = 0; y < rows_a.size(); ++y) {
    out.error_a.merge(rows_a[y]);
    out.error_b.merge(rows_b[y]);
  }
  for (size_t i = 1; i < texels; ++i) {
    out.base_constant = out.base_constant && std::equal(&out.base_color[i * 4], &out.base_color[i * 4 + 3], &out.base_color[0]);
    out.alpha_constant = out.alpha_constant && out.base_color[i * 4 + 3] == out.base_color[3];
    out.metal_rough_constant =
        out.metal_rough_constant && std::equal(&out.metal_rough[i * 3], &out.metal_rough[i * 3 + 3], &out.metal_rough[0]);
  }
  return out;
}

}  // namespace gltf_pbr
