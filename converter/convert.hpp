// spec-gloss -> metal-rough conversion of a whole asset, with a report of the error each
// material took on against the time it cost.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "converter/bake.hpp"  // MetalnessLevels
#include "converter/error_stats.hpp"
#include "converter/solver.hpp"
#include "core/asset.hpp"
#include "core/image.hpp"         // DecodedImages
#include "gltf_pbr/gltf_pbr.hpp"  // Target

namespace gltf_pbr {

struct ConvertOptions {
  Target target = Target::Metalness;
  SolverSettings solver;
  double specular_tolerance = 2.0;      // ΔE2000: a worse metalness fit gets the extensions (Target::Specular)
  int png_compression = 1;              // libdeflate level 0-9 of baked PNGs (at least 9 for small ones)
  int jpeg_quality = 90;                // quality of base colours baked from JPEG diffuse textures
  // ΔE2000 (judged_error, the sum of two means) a metalness map may add when written with fewer
  // distinct values (fewer_metalness_levels); 0 writes every value the solve gave. At 0.002 no
  // shared asset's error figure moves at the two decimals the benchmarks print, and held-out maps
  // shrink more than under session 37's 0.01 with levels of 2, 4, 8 or 16 only (bench/RESULTS.md,
  // session 39).
  double metalness_tolerance = 0.002;
  size_t max_error_samples = 1u << 16;  // texels sampled for the error statistics (0: all)
  // When set, every image the conversion decodes (its inputs, and the JPEG base colours it measures
  // as written) and every PNG it bakes is kept here as pixels for a later reader in the same run
  // (the preview's scene), which then decodes none of them.
  DecodedImages* keep_decoded = nullptr;
};

struct StageTimes {
  double decode_ms = 0, solve_ms = 0, encode_ms = 0;
  double total() const { return decode_ms + solve_ms + encode_ms; }
  StageTimes& operator+=(const StageTimes& o) {
    decode_ms += o.decode_ms, solve_ms += o.solve_ms, encode_ms += o.encode_ms;
    return *this;
  }
};

// What became of a texture slot a converted material writes.
enum class TextureOutcome {
  None,         // no texture in the slot: factors only
  Baked,        // a new image, baked texel by texel for this material
  Shared,       // the image baked for an earlier material with the same inputs
  InputReused,  // an input image as it was (the baked texels equal it within 8-bit rounding)
  Factor,       // the bake came out constant: a factor instead of a texture
};
const char* texture_outcome_name(TextureOutcome outcome);  // "baked", "shared", "inputReused", ...

// What became of a spec-gloss material.
enum class MaterialOutcome {
  Legacy,     // left as spec-gloss (see the note), or not converted yet
  Metalness,  // core metal-rough
  Specular,   // metal-rough with KHR_materials_specular and _ior (--target specular)
};
const char* material_outcome_name(MaterialOutcome outcome);  // "legacy", "metalness", "specular"

struct MaterialOutputs {
  TextureOutcome base_color = TextureOutcome::None, metallic_roughness = TextureOutcome::None;
};

struct MaterialReport {
  int index = -1;
  std::string name;
  MaterialOutcome outcome = MaterialOutcome::Legacy;
  // Why, for Legacy and Specular, for Metalness under Target::Specular's appearance test, and for
  // a material that keeps its JPEG diffuse as it is (both figures).
  std::string note;
  long long texels = 0;  // texels solved (1 for a factor-only material)
  size_t error_samples = 0;
  // ΔE2000 of what was written, against legacy reading A (the one solved for) and B; std::nullopt
  // where nothing was measured (a material left as spec-gloss), reported as null, never as 0.
  std::optional<ReflectanceError> error_a, error_b;
  // The metalness map's distinct values as solved and as written, where a map was baked.
  std::optional<MetalnessLevels> metalness_levels;
  MaterialOutputs outputs;
  StageTimes times;
};

struct ConversionReport {
  std::vector<MaterialReport> materials;
  std::vector<std::string> warnings;
  int textures_baked = 0, textures_reused = 0, textures_shared = 0;
  int textures_removed = 0, images_removed = 0, samplers_removed = 0;
  long images_decoded = 0;  // inputs, and the JPEG base colours decoded again to measure what was written
  // Each material's stage times summed. Bakes of textures up to 1 Mtexel are made several at once,
  // one thread each, so the sum can exceed the conversion's wall time, `wall_ms`.
  StageTimes times;
  double wall_ms = 0;
  bool extension_lists_changed = false;
  // False when there was nothing to convert: the asset can be copied as is.
  bool changed() const { return !materials.empty() || extension_lists_changed; }
};

// Converts every KHR_materials_pbrSpecularGlossiness material in place. Throws InputError for
// input it refuses (NaN or Inf factors, out-of-range references), naming the JSON pointer.
ConversionReport convert(Asset& asset, const ConvertOptions& options = {});

}  // namespace gltf_pbr
