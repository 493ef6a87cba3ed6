// Texel-by-texel baking of spec-gloss textures into baseColor and metallicRoughness texels.
#pragma once
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <optional>
#include <span>
#include <vector>

#include "converter/error_stats.hpp"
#include "converter/solver.hpp"
#include "core/image.hpp"

namespace gltf_pbr {

struct BakeInputs {
  const Pixels* diffuse = nullptr;     // sRGB RGB(A), or null for a factor
  const Pixels* spec_gloss = nullptr;  // sRGB RGB + linear A, or null for factors
  glm::vec4 diffuse_factor{1.0f};
  glm::vec3 specular_factor{1.0f};
  float glossiness_factor = 1.0f;
  int width = 1, height = 1;  // the larger input resolution
  // Also sample the error of the KHR_materials_specular route (base = diffuse, F0 = specular),
  // which --target specular may pick instead of the solve.
  bool measure_extension_route = false;
  // The diffuse's own texel buffer (&diffuse->bytes), handed over by a caller that holds the only
  // reference: when the diffuse is 8-bit with the base colour's channels, the bake writes base
  // colour over it (each texel is read before its own bytes are written) and moves it into the
  // result, so a full-size RGB(A) buffer fewer is alive at once (48 MB at 4096²). The buffer is
  // empty afterwards when taken; a diffuse the bake cannot write over is left as it was.
  TexelBytes* overwrite_diffuse = nullptr;
  // The caller measures the error of the base colour it writes (measure_as_written), which may
  // differ from the bake's (a JPEG): the bake keeps each error sample's legacy texel
  // (BakedTexels::sampled_legacy) instead of measuring it.
  bool measure_as_written = false;
  // Keep each error sample's legacy texel as well as measuring it, for a caller that may change
  // the texels and measure them again (fewer_metalness_levels).
  bool keep_sampled_legacy = false;
};

struct BakedTexels {
  int width = 0, height = 0;
  // sRGB RGB and linear A (glTF 2.0 section 3.9.2). RGB only (base_channels 3) when the diffuse
  // has no alpha channel: alpha is then the diffuse factor's, kept in `alpha` alone.
  TexelBytes base_color;
  int base_channels = 4;
  std::uint8_t alpha = 255;  // the first texel's alpha: all of them when alpha_constant
  // Linear metalness, a byte a texel; roughness a byte a texel only when the glossiness varies by
  // texel (a specularGlossiness texture), else empty and 255 everywhere: the material's
  // roughnessFactor then carries 1 - glossiness at full precision (glTF 2.0 section 3.9.2 multiplies
  // the two), so materials that differ only in their glossiness factor share one map. Planes, not
  // the interleaved map, while the bake runs: a third of the memory where the roughness is a factor
  // (CesiumMilkTruck's 2048² map: 4 MB, not 12). Where no later step reads them, convert frees
  // them once interleaved for the encoder, and gives base_color to it (converter/convert.cpp):
  // afterwards only a constant map's first texel is read.
  TexelBytes metalness, roughness;
  std::uint8_t first_roughness = 255;
  bool base_constant = true, alpha_constant = true, metal_rough_constant = true;
  // The base colour equals the 8-bit diffuse within the solve's rounding (1 code in RGB; alpha
  // exactly), so the diffuse image can stand for it (the caller also checks the factor); the
  // error reported stays the bake's, which the diffuse matches to that code value.
  bool equals_diffuse = false;
  ErrorAccumulator error_a, error_b;          // against legacy readings A and B
  ErrorAccumulator extension_a, extension_b;  // the extension route's, when measured (else empty)
  size_t sample_stride = 1;                   // error sample s is texel s × sample_stride
  std::vector<SpecGloss> sampled_legacy;  // each sample's legacy texel, with measure_as_written or keep_sampled_legacy

  // The metallicRoughness texels as glTF stores them: RGB, R unused (0), G roughness, B metalness.
  TexelBytes metal_rough() const;
  // The same map, when it varies (not metal_rough_constant), as palette indices straight from the
  // planes if it holds at most 256 (roughness, metalness) pairs: colours by first appearance, as
  // filter_png's scan of metal_rough() finds them (core/image.hpp filter_palette_png), so the file
  // is the same. std::nullopt above 256. (A constant map of (0, 0) would be a grey image there.)
  struct Indexed {
    TexelBytes indices;
    std::vector<std::uint32_t> palette;  // RGBA packed, little-end first
  };
  std::optional<Indexed> metal_rough_indexed() const;
};

// Every error_sample_stride()-th texel, in texel order, is an error sample: at most
// `max_error_samples` of `texels` (0: all). compare samples the same texels.
size_t error_sample_stride(size_t texels, size_t max_error_samples);

// Solves every texel (factor x texel, each in its colour space). Inputs of other sizes are
// resampled to width x height first by the caller.
BakedTexels bake(const BakeInputs& inputs, const SolverSettings& settings, size_t max_error_samples);

// Measures error_a and error_b of a bake made with measure_as_written on the base colour as the
// file holds it: `base` is 8-bit sRGB with `channels` (3 or 4) a texel on the bake's grid, the
// bake's own texels or the decode of their lossy encoding. So the report gives the error of what
// was written.
void measure_as_written(BakedTexels& texels, std::span<const std::uint8_t> base, int channels,
                        const SolverSettings& settings);

// The dielectric copy on the same samples: the diffuse image kept as it is under the diffuse
// factor, metallic 0, the roughness 1 - glossiness. error_a and error_b as measure_as_written sets
// them, for a material that keeps its diffuse image (converter/convert.cpp).
void measure_dielectric_copy(BakedTexels& texels, const SolverSettings& settings);

// A metalness map written with fewer distinct values than the solve gave where that costs almost
// no error: its bytes shrink with the values' entropy (BoxTextured's 51 values in 5: 5,586 bytes
// to 2,766). The values move to the fewest levels, from 2 to kMostMetalnessLevels (fewer than the
// map holds), whose judged_error, with the base colour as the file holds it kept (`base_at_samples`, read at
// the error samples only, so the image may go to its encoder meanwhile), rises by at most
// `tolerance` ΔE2000 on every error sample; a candidate is looked at on kDecisionSamples of them
// first, and one that rises by more there is not tried on all. The levels are the 1-D k-means of
// the map's values, each weighed by its texels, solved exactly by dynamic programming over the
// sorted values (Wang & Song 2011, "Ckmeans.1d.dp: optimal k-means clustering in one dimension"),
// except that a level holding 0 or 255 stays there: a pure dielectric or a pure metal stays exact.
// Levels moved within their clusters to lower this figure further made the rendered look worse
// (bench/RESULTS.md, session 38), so they stay at the means. Needs the samples' legacy texels
// (keep_sampled_legacy or measure_as_written) and error_a and error_b as measured on that base
// colour with the map as solved; they become the figures of the map as written. Distinct values
// before and after; equal when the map is left as it was.
inline constexpr size_t kDecisionSamples = 4096;
inline constexpr int kMostMetalnessLevels = 16;
struct MetalnessLevels {
  int solved = 0, written = 0;
};
MetalnessLevels fewer_metalness_levels(BakedTexels& texels, std::span<const std::uint8_t> base_at_samples,
                                       const SolverSettings& settings, double tolerance);
// The base colour `base` (8-bit sRGB, `channels` 3 or 4 a texel on the bake's grid) at each error
// sample, RGB in sample order: what measuring the texels as written reads of it.
TexelBytes base_at_samples(const BakedTexels& texels, std::span<const std::uint8_t> base, int channels);
// The level each metalness byte moves to with `levels` (at least 2) levels (see above), from the
// map's histogram (texels a value); a value no texel holds keeps itself.
std::array<std::uint8_t, 256> metalness_levels(const std::array<std::uint64_t, 256>& histogram, int levels);

// Reading A's figures of both, finished, on about `samples` of the error samples (every k-th, k odd):
// enough to choose between them at a fraction of a full measure's cost.
struct WrittenAgainstCopy {
  ReflectanceError written, copy;
  size_t samples = 0;
};
WrittenAgainstCopy written_against_copy(const BakedTexels& texels, std::span<const std::uint8_t> base, int channels,
                                        const SolverSettings& settings, size_t samples);

}  // namespace gltf_pbr
