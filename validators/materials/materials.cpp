// PBR_* plausibility of every material, from factors and texel by texel from textures, against the
// ranges of rules/materials.json (DESIGN.md, "Plausibility ranges").
#include "validators/materials/materials.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <set>
#include <vector>

#include "core/color.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "core/material_model.hpp"
#include "core/parallel.hpp"
#include "rules/issue_sink.hpp"
#include "validators/materials/f0_reference.hpp"
#include "validators/materials/material_checks.hpp"

namespace gltf_pbr {
namespace {

// Where a texel fails, in the heat map (documented in materials.hpp).
enum class HeatKind { None, TooDark, TooBright, OutOfRange };

enum PbrCheck {
  kDielectricF0TooLow,
  kDielectricF0TooHigh,
  kDielectricSpecularChromatic,
  kMetalF0TooDark,
  kF0AboveOne,
  kAlbedoTooDark,
  kAlbedoTooBright,
  kMetalWithDiffuse,
  kEnergyNotConserved,
  kPartialMetalness,
  kRoughnessZero,
  kPbrCheckCount
};

struct CheckSpec {
  const char* code;
  HeatKind heat;
};
constexpr std::array<CheckSpec, kPbrCheckCount> kChecks{{
    {"PBR_DIELECTRIC_F0_TOO_LOW", HeatKind::TooDark},
    {"PBR_DIELECTRIC_F0_TOO_HIGH", HeatKind::TooBright},
    {"PBR_DIELECTRIC_SPECULAR_CHROMATIC", HeatKind::OutOfRange},
    {"PBR_METAL_F0_TOO_DARK", HeatKind::TooDark},
    {"PBR_F0_ABOVE_ONE", HeatKind::None},  // real (gold): information, not painted as a failure
    {"PBR_ALBEDO_TOO_DARK", HeatKind::TooDark},
    {"PBR_ALBEDO_TOO_BRIGHT", HeatKind::TooBright},
    {"PBR_METAL_WITH_DIFFUSE", HeatKind::OutOfRange},
    {"PBR_ENERGY_NOT_CONSERVED", HeatKind::TooBright},
    {"PBR_PARTIAL_METALNESS", HeatKind::OutOfRange},
    {"PBR_ROUGHNESS_ZERO", HeatKind::OutOfRange},
}};
static_assert(kPbrCheckCount <= 16, "the per-texel failure mask is 16 bits");

// A texel is judged as a metal from metalness 0.5 up (the midpoint; the blend in between is
// PBR_PARTIAL_METALNESS's concern). For legacy materials the estimated metalness crosses 0.5 at
// mean F0 ~0.245, between the brightest gem (0.22) and the darkest metal (0.45).
constexpr float kMetalFrom = 0.5f;
// Below this F0 the hue of a dielectric specular is 8-bit quantisation noise, not a colour.
constexpr float kChromaticFloor = 0.01f;
// Float rounding of factor products (0.85 + 0.15 must not exceed 1).
constexpr float kSumTolerance = 1e-4f;

float mean3(glm::vec3 v) { return (v.x + v.y + v.z) / 3.0f; }
float max3(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }
float min3(glm::vec3 v) { return std::min(v.x, std::min(v.y, v.z)); }
// ITU-R BT.709 relative luminance of linear sRGB.
float luminance(glm::vec3 v) { return glm::dot(v, glm::vec3(0.2126f, 0.7152f, 0.0722f)); }

glm::vec3 energy_sum(const SurfaceSample& s) { return s.stored_diffuse + glm::min(s.f0, glm::vec3(1.0f)); }

struct Limits {
  float min_f0 = 0, max_gem_f0 = 0, max_saturation = 0, min_metal_f0 = 0, max_f0 = 0, min_luminance = 0,
        max_luminance = 0, max_metal_diffuse = 0, max_sum = 0, min_partial = 0, max_partial = 0;
};

Limits limits_from(const RuleSet& rules, const std::array<bool, kPbrCheckCount>& enabled) {
  Limits l;
  auto get = [&](int check, const char* name) {
    return enabled[static_cast<size_t>(check)]
               ? static_cast<float>(rules.at(kChecks[static_cast<size_t>(check)].code).threshold(name))
               : 0.0f;
  };
  l.min_f0 = get(kDielectricF0TooLow, "min_f0");
  l.max_gem_f0 = get(kDielectricF0TooHigh, "max_gem_f0");
  l.max_saturation = get(kDielectricSpecularChromatic, "max_saturation");
  l.min_metal_f0 = get(kMetalF0TooDark, "min_mean_f0");
  l.max_f0 = get(kF0AboveOne, "max_f0");
  l.min_luminance = get(kAlbedoTooDark, "min_luminance");
  l.max_luminance = get(kAlbedoTooBright, "max_luminance");
  l.max_metal_diffuse = get(kMetalWithDiffuse, "max_diffuse_luminance");
  l.max_sum = get(kEnergyNotConserved, "max_sum");
  l.min_partial = get(kPartialMetalness, "min_metalness");
  l.max_partial = get(kPartialMetalness, "max_metalness");
  return l;
}

// Whether `check` fails at this sample; `badness` grows with how far it fails, so the worst
// texel is the one with the largest badness.
bool fails(int check, const SurfaceSample& s, bool legacy, const Limits& l, float* badness) {
  const bool metal = s.metalness >= kMetalFrom;
  switch (check) {
    case kDielectricF0TooLow:
      *badness = -mean3(s.dielectric_f0);
      return !metal && mean3(s.dielectric_f0) < l.min_f0;
    case kDielectricF0TooHigh:
      *badness = mean3(s.dielectric_f0);
      return !metal && mean3(s.dielectric_f0) > l.max_gem_f0;
    case kDielectricSpecularChromatic: {
      const float top = max3(s.dielectric_f0);
      const float saturation = top > 0.0f ? (top - min3(s.dielectric_f0)) / top : 0.0f;
      *badness = saturation;
      return !metal && top >= kChromaticFloor && saturation > l.max_saturation;
    }
    case kMetalF0TooDark:
      *badness = -mean3(s.metal_f0);
      return metal && mean3(s.metal_f0) < l.min_metal_f0;
    case kF0AboveOne:
      *badness = max3(s.f0);
      return max3(s.f0) > l.max_f0;
    case kAlbedoTooDark:
      *badness = -luminance(s.albedo);
      return !metal && luminance(s.albedo) < l.min_luminance;
    case kAlbedoTooBright:
      *badness = luminance(s.albedo);
      return !metal && luminance(s.albedo) > l.max_luminance;
    case kMetalWithDiffuse:
      // Only the legacy model stores a metal's diffuse; in metal-rough, diffuse on a metal texel
      // comes from partial metalness, which PBR_PARTIAL_METALNESS reports.
      *badness = luminance(s.c_diff);
      return legacy && metal && luminance(s.c_diff) > l.max_metal_diffuse;
    case kEnergyNotConserved: {
      // F0 above 1 on its own is measured gold (PBR_F0_ABOVE_ONE); what the diffuse adds is not.
      const float sum = max3(energy_sum(s));
      *badness = sum;
      return sum > l.max_sum + kSumTolerance;
    }
    case kPartialMetalness:
      *badness = 0.5f - std::abs(s.metalness - 0.5f);
      return !legacy && s.metalness > l.min_partial && s.metalness < l.max_partial;
    case kRoughnessZero:
      *badness = 0.0f;
      return s.roughness <= 0.0f;
  }
  return false;
}

// The textures each check reads, per model; the others are not decoded for it.
std::vector<TextureRole> roles_read(int check, bool legacy) {
  using R = TextureRole;
  if (legacy) {
    switch (check) {
      case kAlbedoTooDark:
      case kAlbedoTooBright:
      case kMetalWithDiffuse:
      case kEnergyNotConserved:
        return {R::Diffuse, R::SpecularGlossiness};
      default:
        return {R::SpecularGlossiness};  // F0, the metal estimate and glossiness
    }
  }
  switch (check) {
    case kDielectricF0TooLow:
    case kDielectricF0TooHigh:
    case kDielectricSpecularChromatic:
      return {R::MetallicRoughness, R::Specular, R::SpecularColor};
    case kMetalF0TooDark:
    case kAlbedoTooDark:
    case kAlbedoTooBright:
      return {R::MetallicRoughness, R::BaseColor};
    case kPartialMetalness:
    case kRoughnessZero:
      return {R::MetallicRoughness};
    default:
      return {R::MetallicRoughness, R::BaseColor, R::Specular, R::SpecularColor};
  }
}

std::string texture_or_factor(const MaterialInputs& m, TextureRole role, const char* factor) {
  if (m.texture(role).present()) return m.texture(role).pointer;
  auto it = m.factor_pointers.find(factor);
  return it != m.factor_pointers.end() ? it->second : m.pointer;
}

// The JSON pointer of what drives a check's value: the texture when there is one, else the factor.
std::string pointer_for(int check, const MaterialInputs& m) {
  using R = TextureRole;
  if (m.model == MaterialModel::SpecGloss) {
    switch (check) {
      case kAlbedoTooDark:
      case kAlbedoTooBright:
      case kMetalWithDiffuse:
        return texture_or_factor(m, R::Diffuse, "diffuseFactor");
      case kRoughnessZero:
        return texture_or_factor(m, R::SpecularGlossiness, "glossinessFactor");
      case kEnergyNotConserved:
        // The specular is what makes diffuse + F0 exceed 1, unless only the diffuse varies.
        if (!m.texture(R::SpecularGlossiness).present() && m.texture(R::Diffuse).present())
          return m.texture(R::Diffuse).pointer;
        return texture_or_factor(m, R::SpecularGlossiness, "specularFactor");
      default:  // F0 checks
        return texture_or_factor(m, R::SpecularGlossiness, "specularFactor");
    }
  }
  switch (check) {
    case kDielectricF0TooLow:
    case kDielectricF0TooHigh:
    case kDielectricSpecularChromatic:
      if (m.texture(R::SpecularColor).present()) return m.texture(R::SpecularColor).pointer;
      if (m.texture(R::Specular).present()) return m.texture(R::Specular).pointer;
      if (m.has_specular && m.specular_color != glm::vec3(1.0f)) return m.factor_pointers.at("specularColorFactor");
      if (m.has_specular && (m.specular != 1.0f || !m.has_ior)) return m.factor_pointers.at("specularFactor");
      if (m.has_ior) return m.factor_pointers.at("ior");
      return m.pointer;
    case kPartialMetalness:
      return texture_or_factor(m, R::MetallicRoughness, "metallicFactor");
    case kRoughnessZero:
      return texture_or_factor(m, R::MetallicRoughness, "roughnessFactor");
    default:
      return texture_or_factor(m, R::BaseColor, "baseColorFactor");
  }
}

std::string srgb8_of(float linear) {
  return std::to_string(static_cast<int>(std::lround(linear_to_srgb(linear) * 255.0f)));
}

// What the worst sample looked like, naming the reference F0 it most resembles.
std::string describe_sample(int check, const SurfaceSample& s, bool legacy) {
  switch (check) {
    case kDielectricF0TooLow:
    case kDielectricF0TooHigh:
    case kDielectricSpecularChromatic:
      return describe_f0(s.dielectric_f0);
    case kMetalF0TooDark:
      return describe_f0(s.metal_f0);
    case kAlbedoTooDark:
    case kAlbedoTooBright:
      return "albedo " + format_rgb(s.albedo) + ", luminance " + format_number(luminance(s.albedo), 3) + " (sRGB " +
             srgb8_of(luminance(s.albedo)) + ")";
    case kMetalWithDiffuse:
      return "diffuse weight " + format_rgb(s.c_diff) + " (luminance " + format_number(luminance(s.c_diff), 3) +
             ") beside " + describe_f0(s.metal_f0);
    case kEnergyNotConserved:
      return (legacy ? "diffuse " + format_rgb(s.albedo) : "c_diff " + format_rgb(s.c_diff)) + " + F0 " +
             format_rgb(s.f0) + " = " + format_rgb(energy_sum(s)) + "; " + describe_f0(s.f0);
    case kPartialMetalness:
      return "metalness " + format_number(s.metalness, 2) + ", " + describe_f0(s.f0);
    case kRoughnessZero:
      return std::string(legacy ? "glossiness 1" : "roughness 0") + ", " + describe_f0(s.f0);
    default:
      return describe_f0(s.f0);
  }
}

// The message's arguments after the worst sample: the thresholds that judged, in the order the
// rule's message names them, and the profile they were read for (rules/rule_set.hpp).
std::vector<std::string> threshold_arguments(int check, const Rule& rule) {
  auto t = [&](const char* name) { return format_number(rule.threshold(name), 3); };
  auto srgb = [&](const char* name) { return srgb8_of(static_cast<float>(rule.threshold(name))); };
  std::vector<std::string> arguments;
  switch (check) {
    case kDielectricF0TooLow:
      arguments = {t("min_f0")};
      break;
    case kDielectricF0TooHigh:
      arguments = {t("max_gem_f0")};
      break;
    case kDielectricSpecularChromatic:
      arguments = {t("max_saturation")};
      break;
    case kMetalF0TooDark:
      arguments = {t("min_mean_f0")};
      break;
    case kF0AboveOne:
      arguments = {t("max_f0")};
      break;
    case kAlbedoTooDark:
      arguments = {t("min_luminance"), srgb("min_luminance")};
      break;
    case kAlbedoTooBright:
      arguments = {t("max_luminance"), srgb("max_luminance")};
      break;
    case kMetalWithDiffuse:
      arguments = {t("max_diffuse_luminance")};
      break;
    case kEnergyNotConserved:
      arguments = {t("max_sum")};
      break;
    case kPartialMetalness:
      arguments = {t("min_metalness"), t("max_metalness"), format_number(rule.threshold("max_coverage_percent"), 1)};
      break;
    default:
      break;
  }
  if (rule.profile)
    arguments.push_back(std::string(rule.configured ? "config-adjusted " : "") + rule_profile_name(*rule.profile));
  return arguments;
}

struct Finding {
  std::uint64_t failing = 0;
  float worst_badness = -INFINITY;
  SurfaceSample worst;
};

// Texels judged a band at least: below it, a material's texels are judged on the calling thread.
constexpr size_t kTexelsABand = 1 << 18;

// What the enabled checks say of one texel: which fail and how badly, and its heat-map grey.
struct TexelVerdict {
  std::uint16_t failing = 0;  // one bit a check
  std::uint8_t grey = 0;
  std::array<float, kPbrCheckCount> badness{};  // of the failing checks
};

// Verdicts by the texel's stored 8-bit values, direct-mapped. Within one material a verdict
// depends on those values alone, and textures repeat them: a hit skips the colour decoding, the
// surface evaluation and every check, and gives the same verdict (bench/RESULTS.md, "validate:
// one verdict a distinct texel"). Bounded: at most 16384 entries (1.3 MB) a band of a material.
class TexelVerdictCache {
 public:
  // The RGBA bytes of each role's texel, 0 where the role has no texture. Within one material a
  // role's channel count is fixed, so the packing is unambiguous.
  using Key = std::array<std::uint32_t, kTextureRoleCount>;

  explicit TexelVerdictCache(size_t texels) : entries_(std::bit_ceil(std::clamp<size_t>(texels, 1, 16384))) {}

  // The verdict of `key`, from `judge()` when it is not cached.
  template <class Judge>
  const TexelVerdict& find(const Key& key, Judge&& judge) {
    std::uint64_t hash = 0;
    for (std::uint32_t k : key) hash = (hash ^ k) * 0x9E3779B97F4A7C15ull;  // multiply by 2^64 / golden ratio
    Entry& entry = entries_[(hash ^ (hash >> 32)) & (entries_.size() - 1)];
    if (!entry.used || entry.key != key) entry.key = key, entry.verdict = judge(), entry.used = true;
    return entry.verdict;
  }

  // Whether every texture of the material is 8-bit, so that its texels have keys (16-bit and
  // float textures are judged texel by texel, uncached).
  static bool packs(const std::array<const Pixels*, kTextureRoleCount>& pixels) {
    return std::ranges::all_of(pixels, [](const Pixels* p) { return !p || (!p->bytes.empty() && p->channels <= 4); });
  }
  static Key key_at(const std::array<const Pixels*, kTextureRoleCount>& pixels, int x, int y) {  // when packs()
    Key key{};
    for (size_t role = 0; role < key.size(); ++role) {
      const Pixels* p = pixels[role];
      if (!p) continue;
      const size_t channels = static_cast<size_t>(p->channels);
      const std::uint8_t* texel =
          &p->bytes[(static_cast<size_t>(y) * static_cast<size_t>(p->width) + static_cast<size_t>(x)) * channels];
      for (size_t c = 0; c < channels; ++c) key[role] |= static_cast<std::uint32_t>(texel[c]) << (8 * c);
    }
    return key;
  }

 private:
  struct Entry {
    Key key{};
    bool used = false;
    TexelVerdict verdict;
  };
  std::vector<Entry> entries_;
};

// Heat-map colours (documented in materials.hpp): passing texels are a dimmed grey of the albedo
// so the failures stand out; a texel that fails several ways shows the first of out of range,
// too bright, too dark.
constexpr std::array<std::uint8_t, 3> kTooDarkColour{0, 0, 255};
constexpr std::array<std::uint8_t, 3> kTooBrightColour{255, 0, 0};
constexpr std::array<std::uint8_t, 3> kOutOfRangeColour{255, 255, 0};

void write_heat_map(const fs::path& file, int width, int height, const std::vector<std::uint16_t>& masks,
                    const std::vector<std::uint8_t>& greys, std::uint16_t reported) {
  std::vector<std::uint8_t> rgb(masks.size() * 3);
  for (size_t i = 0; i < masks.size(); ++i) {
    bool dark = false, bright = false, out = false;
    for (int check = 0; check < kPbrCheckCount; ++check) {
      if (!(masks[i] & reported & (1u << check))) continue;
      const HeatKind kind = kChecks[static_cast<size_t>(check)].heat;
      dark |= kind == HeatKind::TooDark;
      bright |= kind == HeatKind::TooBright;
      out |= kind == HeatKind::OutOfRange;
    }
    std::array<std::uint8_t, 3> colour{greys[i], greys[i], greys[i]};
    if (out)
      colour = kOutOfRangeColour;
    else if (bright)
      colour = kTooBrightColour;
    else if (dark)
      colour = kTooDarkColour;
    std::copy(colour.begin(), colour.end(), rgb.begin() + static_cast<std::ptrdiff_t>(i * 3));
  }
  try {
    const Bytes png = encode_png(rgb, width, height, 3, 6);
    fs::create_directories(file.parent_path());
    AtomicWriteSet files;
    files.stage(file, png);
    files.commit();
  } catch (const std::exception& error) {
    // The heat-map folder is the user's input: an unwritable one is their error, named.
    throw InputError(file.string(), "", std::string("cannot write the heat map: ") + error.what());
  }
}

}  // namespace

void add_issue(const RuleSet& rules, const std::string& code, const std::vector<std::string>& arguments,
               const std::string& pointer, Report& report) {
  IssueSink(rules, report).at_text(code, pointer, arguments);
}

const Pixels* TexelSource::get(int image, const RuleSet& rules, Report& report) {
  if (failed_.contains(image)) return nullptr;
  try {
    return &decoded_.get(asset_, image);
  } catch (const std::exception& error) {
    failed_.insert(image);
    if (rules.enabled("IMAGE_UNDECODABLE"))
      add_issue(rules, "IMAGE_UNDECODABLE", {error.what()}, pointer("images", image), report);
    return nullptr;
  }
}

void check_material_plausibility(const Asset& asset, const RuleSet& rules, const MaterialCheckOptions& options,
                                 TexelSource& images, Report& report) {
  std::array<bool, kPbrCheckCount> enabled{};
  for (int check = 0; check < kPbrCheckCount; ++check)
    enabled[static_cast<size_t>(check)] = rules.enabled(kChecks[static_cast<size_t>(check)].code);
  const Limits limits = limits_from(rules, enabled);

  const auto& model = asset.model;
  for (int index = 0; index < static_cast<int>(model.materials.size()); ++index) {
    // KHR_materials_unlit: the base colour is shown as is, no reflectance model to judge.
    if (model.materials[static_cast<size_t>(index)].extensions.contains("KHR_materials_unlit")) continue;
    const MaterialInputs material = read_material_inputs(model, index);
    const bool legacy = material.model == MaterialModel::SpecGloss;
    if (legacy && rules.enabled("PBR_LEGACY_SPEC_GLOSS"))
      add_issue(rules, "PBR_LEGACY_SPEC_GLOSS", {},
                material.pointer + "/extensions/KHR_materials_pbrSpecularGlossiness", report);

    // Decode only the textures that an enabled check of this model reads.
    std::array<bool, kTextureRoleCount> role_needed{};
    bool any_check = false;
    for (int check = 0; check < kPbrCheckCount; ++check) {
      if (!enabled[static_cast<size_t>(check)]) continue;
      any_check = true;
      for (TextureRole role : roles_read(check, legacy)) role_needed[static_cast<size_t>(role)] = true;
    }
    if (!any_check) continue;
    std::array<const Pixels*, kTextureRoleCount> pixels{};
    const Pixels* largest = nullptr;
    int grid_texture = -1;  // names the heat map
    bool undecodable = false;
    for (int role = 0; role < kTextureRoleCount; ++role) {
      const MaterialTexture& texture = material.textures[static_cast<size_t>(role)];
      if (!role_needed[static_cast<size_t>(role)] || !texture.present()) continue;
      pixels[static_cast<size_t>(role)] = images.get(texture.image, rules, report);
      const Pixels* p = pixels[static_cast<size_t>(role)];
      undecodable |= !p;
      if (p &&
          (!largest || static_cast<long>(p->width) * p->height > static_cast<long>(largest->width) * largest->height))
        largest = p, grid_texture = texture.texture;
    }

    // Judging the factors alone would be wrong where a texture multiplies them; IMAGE_UNDECODABLE
    // has said that these texels went unchecked.
    if (undecodable) continue;

    // The texels judged are the texels the converter bakes: every texture on the bake's grid,
    // resampled to it the same way where its size differs. Factor-only: one sample (1 x 1). The
    // grid is bounded as the bake's is (convert refuses it; here the material's texels go unchecked).
    const TexelGrid grid = bake_grid(pixels);
    std::vector<Pixels> resampled;         // this material's, freed with it
    resampled.reserve(kTextureRoleCount);  // stable addresses: `pixels` points into it
    std::string not_checked;
    if (static_cast<std::uint64_t>(grid.width) * static_cast<std::uint64_t>(grid.height) > max_image_pixels())
      not_checked = "its textures bake at " + std::to_string(grid.width) + "x" + std::to_string(grid.height) +
                    ", above the limit of " + std::to_string(max_image_pixels()) + " pixels (--max-image-pixels)";
    for (int role = 0; role < kTextureRoleCount && not_checked.empty(); ++role) {
      const Pixels*& p = pixels[static_cast<size_t>(role)];
      if (!p || (p->width == grid.width && p->height == grid.height)) continue;
      try {
        p = &resampled.emplace_back(resize(*p, grid.width, grid.height));
      } catch (const std::exception& error) {
        not_checked = std::string("cannot resample ") + texture_role_name(static_cast<TextureRole>(role)) + " to " +
                      std::to_string(grid.width) + "x" + std::to_string(grid.height) + ": " + error.what();
      }
    }
    if (!not_checked.empty()) {
      if (rules.enabled("PBR_TEXELS_NOT_CHECKED"))
        add_issue(rules, "PBR_TEXELS_NOT_CHECKED", {not_checked}, material.pointer, report);
      continue;
    }

    // Texels of textures read through different texCoord sets or KHR_texture_transform meet at
    // different UVs on the mesh; combined at equal UV they are not what renders. Say so. A single
    // texture is checked texel by texel, whatever maps it onto the mesh.
    std::string mapping_note;
    {
      std::set<int> tex_coords;
      bool transformed = false;
      int textures = 0;
      for (int role = 0; role < kTextureRoleCount; ++role) {
        if (!pixels[static_cast<size_t>(role)]) continue;
        ++textures;
        tex_coords.insert(material.textures[static_cast<size_t>(role)].tex_coord);
        transformed |= material.textures[static_cast<size_t>(role)].transformed;
      }
      if (textures > 1 && (tex_coords.size() > 1 || transformed))
        mapping_note =
            " (its textures use different texCoord sets or KHR_texture_transform: texels were combined at equal UV, "
            "not as the mesh maps them)";
    }

    const int width = grid.width, height = grid.height;
    const size_t total = static_cast<size_t>(width) * static_cast<size_t>(height);
    const bool heat_maps = !options.heatmaps_dir.empty() && largest;
    std::vector<std::uint16_t> masks(heat_maps ? total : 0);
    std::vector<std::uint8_t> greys(heat_maps ? total : 0);
    std::array<Finding, kPbrCheckCount> findings;
    const auto sample_at = [&](int x, int y) {
      TexelInputs texels;
      for (int role = 0; role < kTextureRoleCount; ++role)
        if (const Pixels* p = pixels[static_cast<size_t>(role)])
          texels.raw[static_cast<size_t>(role)] = texel_rgba(*p, x, y);
      return evaluate_surface(material, texels);
    };
    const auto judge = [&](int x, int y) {
      const SurfaceSample sample = sample_at(x, y);
      TexelVerdict verdict;
      for (int check = 0; check < kPbrCheckCount; ++check) {
        if (!enabled[static_cast<size_t>(check)]) continue;
        float badness = 0.0f;
        if (!fails(check, sample, legacy, limits, &badness)) continue;
        verdict.failing = static_cast<std::uint16_t>(verdict.failing | (1u << check));
        verdict.badness[static_cast<size_t>(check)] = badness;
      }
      if (heat_maps)
        verdict.grey = static_cast<std::uint8_t>(std::lround(linear_to_srgb(luminance(sample.albedo)) * 127.0f));
      return verdict;
    };
    // Rows in bands on the pool, each band with its own verdict table and findings, joined in scan
    // order: the counts add up, and the worst texel is the first of the worst badness, as in one pass.
    const bool cached = TexelVerdictCache::packs(pixels);
    const int bands =
        static_cast<int>(std::clamp<std::int64_t>(static_cast<std::int64_t>(total / kTexelsABand), 1,
                                                  std::min<std::int64_t>(ThreadPool::shared().threads(), height)));
    std::vector<std::array<Finding, kPbrCheckCount>> band_findings(static_cast<size_t>(bands));
    ThreadPool::shared().run(bands, [&](std::int64_t band) {
      const int first_row = static_cast<int>(height * band / bands),
                end_row = static_cast<int>(height * (band + 1) / bands);
      std::array<Finding, kPbrCheckCount>& found = band_findings[static_cast<size_t>(band)];
      TexelVerdictCache cache(cached ? static_cast<size_t>(end_row - first_row) * static_cast<size_t>(width) : 0);
      for (int y = first_row; y < end_row; ++y)
        for (int x = 0; x < width; ++x) {
          TexelVerdict uncached;
          const TexelVerdict& verdict =
              cached ? cache.find(TexelVerdictCache::key_at(pixels, x, y), [&] { return judge(x, y); })
                     : (uncached = judge(x, y));
          for (int check = 0; check < kPbrCheckCount; ++check) {
            if (!(verdict.failing >> check & 1u)) continue;
            Finding& finding = found[static_cast<size_t>(check)];
            ++finding.failing;
            const float badness = verdict.badness[static_cast<size_t>(check)];
            // The first texel of the worst badness, in scan order, as its sample.
            if (badness > finding.worst_badness) finding.worst_badness = badness, finding.worst = sample_at(x, y);
          }
          if (heat_maps) {
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
            masks[i] = verdict.failing;
            greys[i] = verdict.grey;
          }
        }
    });
    for (const std::array<Finding, kPbrCheckCount>& found : band_findings)
      for (size_t check = 0; check < found.size(); ++check) {
        Finding& finding = findings[check];
        finding.failing += found[check].failing;
        if (found[check].worst_badness > finding.worst_badness)
          finding.worst_badness = found[check].worst_badness, finding.worst = found[check].worst;
      }

    std::uint16_t reported = 0;
    for (int check = 0; check < kPbrCheckCount; ++check) {
      const Finding& finding = findings[static_cast<size_t>(check)];
      if (!enabled[static_cast<size_t>(check)] || finding.failing == 0) continue;
      const char* code = kChecks[static_cast<size_t>(check)].code;
      const Rule& rule = rules.at(code);
      const double coverage = 100.0 * static_cast<double>(finding.failing) / static_cast<double>(total);
      // A large share is what makes partial metalness wrong; every other check reports from a
      // small share up, so that scattered bad texels do not drown in the texture.
      const bool report_it = check == kPartialMetalness ? coverage > rule.threshold("max_coverage_percent")
                                                        : coverage >= rule.threshold("min_coverage_percent");
      if (!report_it) continue;
      reported = static_cast<std::uint16_t>(reported | (1u << check));
      std::string detail = describe_sample(check, finding.worst, legacy);
      const std::string where = pointer_for(check, material);
      // A value that comes from a factor fails everywhere or nowhere: no coverage to state.
      const bool from_factor = !where.ends_with("Texture") && finding.failing == total;
      if (total > 1 && !from_factor)
        detail = format_number(coverage, 2) + "% of " + std::to_string(total) + " texels (" + std::to_string(width) +
                 "x" + std::to_string(height) + "), the worst: " + detail + mapping_note;
      std::vector<std::string> arguments{detail};
      for (std::string& argument : threshold_arguments(check, rule)) arguments.push_back(std::move(argument));
      add_issue(rules, code, arguments, where, report);
    }
    if (heat_maps && reported) {
      const std::string stem = asset.path.stem().string();
      write_heat_map(options.heatmaps_dir / heat_map_name(stem, index, grid_texture), width, height, masks, greys,
                     reported);
    }
  }
}

std::string heat_map_name(const std::string& stem, int material, int texture) {
  return stem + "-material" + std::to_string(material) + "-texture" + std::to_string(texture) + ".png";
}

std::optional<std::string> heat_map_stem(std::string_view name) {
  // Read from the end, as heat_map_name appends: ".png", digits, "-texture", digits, "-material".
  const auto drop_suffix = [&](std::string_view suffix) {
    if (!name.ends_with(suffix)) return false;
    name.remove_suffix(suffix.size());
    return true;
  };
  const auto drop_digits = [&] {
    const std::size_t kept = name.find_last_not_of("0123456789") + 1;  // npos + 1 = 0: all digits
    if (kept == name.size()) return false;
    name = name.substr(0, kept);
    return true;
  };
  if (drop_suffix(".png") && drop_digits() && drop_suffix("-texture") && drop_digits() && drop_suffix("-material"))
    return std::string(name);
  return std::nullopt;
}

void validate_materials(const Asset& asset, const RuleSet& rules, const MaterialCheckOptions& options, Report& report) {
  TexelSource images(asset, options.decoded);  // shared: each image is decoded at most once per file
  if (options.materials) check_material_plausibility(asset, rules, options, images, report);
  if (options.textures) check_material_textures(asset, rules, options, images, report);
}

}  // namespace gltf_pbr
