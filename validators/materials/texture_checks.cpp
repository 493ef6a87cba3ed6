// IMAGE_* checks of the images that materials use: normal-map texels, constant images, empty used
// channels of metallicRoughness images, resolution without detail; and power-of-two sizes of every
// image when the structure step does not run.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <span>

#include "core/image_header.hpp"
#include "core/material_model.hpp"
#include "validators/materials/f0_reference.hpp"
#include "validators/materials/material_checks.hpp"

namespace gltf_pbr {
namespace {

int source_of(const tinygltf::Model& model, int texture) {
  if (texture < 0 || static_cast<size_t>(texture) >= model.textures.size()) return -1;
  const int source = model.textures[static_cast<size_t>(texture)].source;
  return source >= 0 && static_cast<size_t>(source) < model.images.size() ? source : -1;
}

// The KTX2 image a texture names through KHR_texture_basisu, or -1.
int ktx2_source(const tinygltf::Texture& texture) {
  const auto found = texture.extensions.find("KHR_texture_basisu");
  if (found == texture.extensions.end() || !found->second.IsObject() || !found->second.Get("source").IsInt()) return -1;
  return found->second.Get("source").GetNumberAsInt();
}

std::string size_text(const Pixels& p) { return std::to_string(p.width) + "x" + std::to_string(p.height); }

std::string coverage_text(std::uint64_t failing, std::uint64_t total) {
  return format_number(100.0 * static_cast<double>(failing) / static_cast<double>(total), 2) + "% of " +
         std::to_string(total) + " texels";
}

// glTF 2.0 spec 3.9.3: a normal texel t decodes to n = 2t - 1, a tangent-space unit vector with z > 0.
void check_normal_map(const Pixels& p, const std::string& where, const RuleSet& rules, Report& report) {
  // A grey image reads as R = G = B (PNG colour expansion): a normal map of (2g-1, 2g-1, 2g-1).
  const int green = p.channels >= 3 ? 1 : 0, blue = p.channels >= 3 ? 2 : 0;
  const bool check_length = rules.enabled("IMAGE_NORMAL_NOT_UNIT");
  const bool check_z = rules.enabled("IMAGE_NORMAL_BACK_FACING");
  const float max_length_error =
      check_length ? static_cast<float>(rules.at("IMAGE_NORMAL_NOT_UNIT").threshold("max_length_error")) : 0.0f;
  std::uint64_t not_unit = 0, back_facing = 0;
  float worst_length = 1.0f, lowest_z = 1.0f;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      const glm::vec3 n(2.0f * p.at(x, y, 0) - 1.0f, 2.0f * p.at(x, y, green) - 1.0f, 2.0f * p.at(x, y, blue) - 1.0f);
      const float length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
      if (std::abs(length - 1.0f) > max_length_error) {
        ++not_unit;
        if (std::abs(length - 1.0f) > std::abs(worst_length - 1.0f)) worst_length = length;
      }
      if (n.z < 0.0f) {
        ++back_facing;
        lowest_z = std::min(lowest_z, n.z);
      }
    }
  const std::uint64_t total = static_cast<std::uint64_t>(p.width) * static_cast<std::uint64_t>(p.height);
  auto share = [&](std::uint64_t failing) { return 100.0 * static_cast<double>(failing) / static_cast<double>(total); };
  if (check_length && not_unit > 0 &&
      share(not_unit) >= rules.at("IMAGE_NORMAL_NOT_UNIT").threshold("min_coverage_percent"))
    add_issue(rules, "IMAGE_NORMAL_NOT_UNIT",
              {coverage_text(not_unit, total) + ", the worst length " + format_number(worst_length, 3),
               format_number(max_length_error, 2)},
              where, report);
  if (check_z && back_facing > 0 &&
      share(back_facing) >= rules.at("IMAGE_NORMAL_BACK_FACING").threshold("min_coverage_percent"))
    add_issue(rules, "IMAGE_NORMAL_BACK_FACING",
              {coverage_text(back_facing, total) + ", the lowest z " + format_number(lowest_z, 3)}, where, report);
}

// Per-channel minimum and maximum, in 8-bit units.
struct ChannelRange {
  std::array<float, 4> low{255, 255, 255, 255}, high{0, 0, 0, 0};
};
// Calls `f` with the image's stored values as a typed span (bytes, shorts or floats) and the
// scale that maps one of them to [0, 1] the way Pixels::value does, so that a pass over every
// value is one tight loop instead of a storage test a value.
template <class F>
auto with_stored_values(const Pixels& p, F&& f) {
  if (!p.bytes.empty()) return f(std::span<const std::uint8_t>(p.bytes.data(), p.bytes.size()), 255.0f);
  if (!p.shorts.empty()) return f(std::span<const std::uint16_t>(p.shorts), 65535.0f);
  return f(std::span<const float>(p.floats), 1.0f);
}

ChannelRange channel_range(const Pixels& p) {
  return with_stored_values(p, [&](auto values, float scale) {
    using Value = typename decltype(values)::value_type;
    const size_t channels = static_cast<size_t>(p.channels);
    ChannelRange r;
    if (values.empty()) return r;
    for (size_t c = 0; c < channels; ++c) {  // a channel a pass: its extremes stay in registers
      Value low = std::numeric_limits<Value>::max(), high = std::numeric_limits<Value>::lowest();
      for (size_t i = c; i < values.size(); i += channels)
        low = std::min(low, values[i]), high = std::max(high, values[i]);
      // The extremes of the stored values are those of the scaled ones: the scaling is monotonic.
      // They join the initial [0, 255] as every value used to (a float image's values beyond it,
      // and NaN, which no comparison takes).
      r.low[c] = std::min(r.low[c], static_cast<float>(low) / scale * 255.0f);
      r.high[c] = std::max(r.high[c], static_cast<float>(high) / scale * 255.0f);
    }
    return r;
  });
}

// The range as RGBA, as glTF samples the image: grey repeats into G and B, grey's alpha is A.
ChannelRange rgba_range(const Pixels& p) {
  ChannelRange r = channel_range(p);
  if (p.channels < 3) {
    if (p.channels == 2) r.low[3] = r.low[1], r.high[3] = r.high[1];
    r.low[1] = r.low[2] = r.low[0];
    r.high[1] = r.high[2] = r.high[0];
  }
  return r;
}

// True when a 2x2 box-filtered half-size image, upsampled bilinearly back, reproduces all but
// `max_outlier_percent` of the texels within `max_error_8bit` in every channel.
bool half_size_reproduces(const Pixels& p, double max_error_8bit, double max_outlier_percent) {
  return with_stored_values(p, [&](auto values, float scale) {
    // Pixels::at, without its storage test.
    const auto at = [&](int x, int y, int c) {
      return static_cast<float>(
                 values[(static_cast<size_t>(y) * static_cast<size_t>(p.width) + static_cast<size_t>(x)) *
                            static_cast<size_t>(p.channels) +
                        static_cast<size_t>(c)]) /
             scale;
    };
    const int hw = p.width / 2, hh = p.height / 2, channels = p.channels;
    std::vector<float> half(static_cast<size_t>(hw) * static_cast<size_t>(hh) * static_cast<size_t>(channels));
    auto half_at = [&](int x, int y, int c) -> float& {
      return half[(static_cast<size_t>(y) * static_cast<size_t>(hw) + static_cast<size_t>(x)) *
                      static_cast<size_t>(channels) +
                  static_cast<size_t>(c)];
    };
    for (int y = 0; y < hh; ++y)
      for (int x = 0; x < hw; ++x)
        for (int c = 0; c < channels; ++c)
          half_at(x, y, c) = 0.25f * (at(2 * x, 2 * y, c) + at(2 * x + 1, 2 * y, c) + at(2 * x, 2 * y + 1, c) +
                                      at(2 * x + 1, 2 * y + 1, c));
    const std::uint64_t total = static_cast<std::uint64_t>(p.width) * static_cast<std::uint64_t>(p.height);
    const auto allowed = static_cast<std::uint64_t>(max_outlier_percent / 100.0 * static_cast<double>(total));
    std::uint64_t outliers = 0;
    for (int y = 0; y < p.height; ++y) {
      // Texel centres of the full image in half-image texel coordinates, clamped at the edges.
      const float fy = std::clamp((static_cast<float>(y) + 0.5f) * 0.5f - 0.5f, 0.0f, static_cast<float>(hh - 1));
      const int y0 = static_cast<int>(fy), y1 = std::min(y0 + 1, hh - 1);
      const float ty = fy - static_cast<float>(y0);
      for (int x = 0; x < p.width; ++x) {
        const float fx = std::clamp((static_cast<float>(x) + 0.5f) * 0.5f - 0.5f, 0.0f, static_cast<float>(hw - 1));
        const int x0 = static_cast<int>(fx), x1 = std::min(x0 + 1, hw - 1);
        const float tx = fx - static_cast<float>(x0);
        for (int c = 0; c < channels; ++c) {
          const float top = half_at(x0, y0, c) + tx * (half_at(x1, y0, c) - half_at(x0, y0, c));
          const float bottom = half_at(x0, y1, c) + tx * (half_at(x1, y1, c) - half_at(x0, y1, c));
          const float value = top + ty * (bottom - top);
          if (std::abs(value - at(x, y, c)) * 255.0f > max_error_8bit) {
            if (++outliers > allowed) return false;
            break;
          }
        }
      }
    }
    return true;
  });
}

}  // namespace

void check_material_textures(const Asset& asset, const RuleSet& rules, const MaterialCheckOptions& options,
                             TexelSource& images, Report& report) {
  const auto& model = asset.model;
  // Images by use: the first textureInfo pointer of each (for the message), normal maps and
  // metallicRoughness images of metal-rough materials separately.
  std::map<int, std::string> used_images, normal_maps, metal_rough_maps;
  // Textures whose only image is KHR_texture_basisu's KTX2: nothing here can read their texels.
  std::set<int> ktx2_images;
  std::string first_ktx2_use;
  auto note = [&](std::map<int, std::string>& uses, int texture, const std::string& where) {
    if (const int image = source_of(model, texture); image >= 0) {
      uses.emplace(image, where);
    } else if (texture >= 0 && static_cast<size_t>(texture) < model.textures.size()) {
      const int ktx2 = ktx2_source(model.textures[static_cast<size_t>(texture)]);
      if (ktx2 >= 0 && static_cast<size_t>(ktx2) < model.images.size() && ktx2_images.insert(ktx2).second &&
          first_ktx2_use.empty())
        first_ktx2_use = where;
    }
  };
  for (int index = 0; index < static_cast<int>(model.materials.size()); ++index) {
    const tinygltf::Material& material = model.materials[static_cast<size_t>(index)];
    const MaterialInputs inputs = read_material_inputs(model, index);
    for (const MaterialTexture& texture : inputs.textures)
      if (texture.texture >= 0) note(used_images, texture.texture, texture.pointer);
    const std::string base = pointer("materials", index);
    const auto& pbr = material.pbrMetallicRoughness;
    // A legacy material's core fallback is what core-only viewers show: its images are used too.
    note(used_images, pbr.baseColorTexture.index, base + "/pbrMetallicRoughness/baseColorTexture");
    note(used_images, pbr.metallicRoughnessTexture.index, base + "/pbrMetallicRoughness/metallicRoughnessTexture");
    note(used_images, material.normalTexture.index, base + "/normalTexture");
    note(used_images, material.occlusionTexture.index, base + "/occlusionTexture");
    note(used_images, material.emissiveTexture.index, base + "/emissiveTexture");
    note(normal_maps, material.normalTexture.index, base + "/normalTexture");
    if (inputs.model == MaterialModel::MetalRough && inputs.texture(TextureRole::MetallicRoughness).present())
      metal_rough_maps.emplace(inputs.texture(TextureRole::MetallicRoughness).image,
                               inputs.texture(TextureRole::MetallicRoughness).pointer);
  }
  if (!ktx2_images.empty() && rules.enabled("IMAGE_KTX2_NOT_CHECKED"))
    add_issue(rules, "IMAGE_KTX2_NOT_CHECKED", {std::to_string(ktx2_images.size())}, first_ktx2_use, report);

  if (rules.enabled("IMAGE_NORMAL_NOT_UNIT") || rules.enabled("IMAGE_NORMAL_BACK_FACING"))
    for (const auto& [image, where] : normal_maps)
      if (const Pixels* p = images.get(image, rules, report)) check_normal_map(*p, where, rules, report);

  if (rules.enabled("IMAGE_CHANNEL_EMPTY")) {
    const float max_value = static_cast<float>(rules.at("IMAGE_CHANNEL_EMPTY").threshold("max_value_8bit"));
    for (const auto& [image, where] : metal_rough_maps) {
      const Pixels* p = images.get(image, rules, report);
      if (!p) continue;
      const ChannelRange range = rgba_range(*p);
      // glTF 2.0 3.9.2: G roughness, B metalness. R (occlusion in ORM packing) or A with content
      // beside an empty used channel points to a packing for another layout.
      std::string elsewhere;
      if (range.high[0] > max_value) elsewhere = "R";
      if ((p->channels == 2 || p->channels == 4) && range.high[3] < 255.0f - max_value)
        elsewhere += elsewhere.empty() ? "A" : " and A";
      const std::string hint =
          elsewhere.empty() ? "" : " while " + elsewhere + " has content (packed for another layout?)";
      if (range.high[1] <= max_value) add_issue(rules, "IMAGE_CHANNEL_EMPTY", {"G (roughness)", hint}, where, report);
      if (range.high[2] <= max_value) add_issue(rules, "IMAGE_CHANNEL_EMPTY", {"B (metalness)", hint}, where, report);
    }
  }

  const bool check_constant = rules.enabled("IMAGE_CONSTANT");
  const bool check_detail = rules.enabled("IMAGE_LARGER_THAN_NEEDED");
  if (check_constant || check_detail) {
    for (const auto& [image, where] : used_images) {
      const Pixels* p = images.get(image, rules, report);
      if (!p) continue;
      const std::string image_pointer = pointer("images", image);
      bool constant = false;
      if (check_constant) {
        const Rule& rule = rules.at("IMAGE_CONSTANT");
        const ChannelRange range = channel_range(*p);
        constant = true;
        std::string value;
        for (int c = 0; c < p->channels; ++c) {
          constant &= range.high[static_cast<size_t>(c)] - range.low[static_cast<size_t>(c)] <=
                      rule.threshold("max_range_8bit");
          value += (c ? ", " : "") +
                   std::to_string(static_cast<int>(
                       std::lround(0.5f * (range.high[static_cast<size_t>(c)] + range.low[static_cast<size_t>(c)]))));
        }
        if (constant)
          add_issue(rules, "IMAGE_CONSTANT",
                    {size_text(*p) + " of 8-bit (" + value + "), used by " + where,
                     format_number(rule.threshold("max_range_8bit"), 0)},
                    image_pointer, report);
      }
      if (check_detail && !constant) {
        const Rule& rule = rules.at("IMAGE_LARGER_THAN_NEEDED");
        const double min_size = rule.threshold("min_size");
        if (p->width >= min_size && p->height >= min_size &&
            half_size_reproduces(*p, rule.threshold("max_error_8bit"), rule.threshold("max_outlier_percent")))
          add_issue(rules, "IMAGE_LARGER_THAN_NEEDED",
                    {size_text(*p) + ", used by " + where + "; " + std::to_string(p->width / 2) + "x" +
                     std::to_string(p->height / 2) + " would do"},
                    image_pointer, report);
      }
    }
  }

  // The structure step's code and message, for every image as it reports them, when it does not
  // run itself. Sizes come from the image header (core/image_header.hpp): this decodes nothing.
  if (options.npot_dimensions && rules.enabled("IMAGE_NPOT_DIMENSIONS"))
    for (size_t image = 0; image < asset.model.images.size(); ++image) {
      // A strided view holds no image (the structure step says IMAGE_BUFFER_VIEW_WITH_BYTESTRIDE).
      const int view = asset.model.images[image].bufferView;
      if (view >= 0 && static_cast<size_t>(view) < asset.model.bufferViews.size() &&
          asset.model.bufferViews[static_cast<size_t>(view)].byteStride != 0)
        continue;
      const ImageHeader header = read_image_header(encoded_image_bytes(asset, static_cast<int>(image)));
      if (has_npot_dimensions(header))
        add_issue(rules, "IMAGE_NPOT_DIMENSIONS", {std::to_string(header.width), std::to_string(header.height)},
                  pointer("images", static_cast<int>(image)), report);
    }
}

}  // namespace gltf_pbr
