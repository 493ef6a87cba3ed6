// Reading the scene's materials and their textures (see scene_materials.hpp).
#include "preview/scene_materials.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "converter/legacy_material.hpp"
#include "core/image_header.hpp"
#include "core/json_pointer.hpp"
#include "core/parallel.hpp"

namespace gltf_pbr::preview {
namespace {

constexpr int kNearest = 9728;  // glTF 2.0 section 5.26 magFilter NEAREST

glm::vec4 vec4_or(const std::vector<double>& v, glm::vec4 fallback) {
  return v.size() == 4 ? glm::vec4(v[0], v[1], v[2], v[3]) : fallback;
}

}  // namespace

void TextureLoader::request(const Asset& asset, int texture_index, int tex_coord,
                            const tinygltf::ExtensionMap& extensions, bool srgb, TextureSlot& slot) {
  const auto& model = asset.model;
  if (texture_index < 0 || texture_index >= static_cast<int>(model.textures.size())) return;
  const tinygltf::Texture& texture = model.textures[static_cast<size_t>(texture_index)];
  if (texture.source < 0 || texture.source >= static_cast<int>(model.images.size())) return;
  slot.tex_coord = tex_coord;
  slot.srgb = srgb;
  if (texture.sampler >= 0 && texture.sampler < static_cast<int>(model.samplers.size())) {
    const auto& sampler = model.samplers[static_cast<size_t>(texture.sampler)];
    slot.wrap_s = sampler.wrapS;
    slot.wrap_t = sampler.wrapT;
    slot.nearest = sampler.magFilter == kNearest;
  }
  // KHR_texture_transform: matrix = Translation * Rotation * Scale, rotation counter-clockwise
  // in UV space as the extension's README writes it.
  if (auto it = extensions.find("KHR_texture_transform"); it != extensions.end()) {
    const tinygltf::Value& t = it->second;
    auto number = [&](const char* key, int i, double fallback) {
      const tinygltf::Value& v = t.Get(key);
      if (!v.IsArray() || static_cast<int>(v.ArrayLen()) <= i) return fallback;
      return v.Get(i).GetNumberAsDouble();
    };
    const double rotation = t.Has("rotation") ? t.Get("rotation").GetNumberAsDouble() : 0.0;
    const double sx = number("scale", 0, 1.0), sy = number("scale", 1, 1.0);
    const double ox = number("offset", 0, 0.0), oy = number("offset", 1, 0.0);
    const double c = std::cos(rotation), s = std::sin(rotation);
    slot.row_u = glm::vec3(static_cast<float>(c * sx), static_cast<float>(s * sy), static_cast<float>(ox));
    slot.row_v = glm::vec3(static_cast<float>(-s * sx), static_cast<float>(c * sy), static_cast<float>(oy));
    slot.has_transform = true;
    if (t.Has("texCoord")) slot.tex_coord = t.Get("texCoord").GetNumberAsInt();
  }
  slot.tex_coord = std::clamp(slot.tex_coord, 0, 1);
  const auto bytes = encoded_image_bytes(asset, texture.source);
  const ImageContentKey key = image_content_key(bytes);
  auto [it, inserted] = job_of_key_.try_emplace(key, jobs_.size());
  if (inserted) jobs_.push_back({bytes, key, asset.path.string() + pointer("images", texture.source), nullptr});
  pending_.push_back({&slot, it->second});
}

void TextureLoader::prepare(Scene& scene) {
  scene.textures.clear();
  for (Job& job : jobs_) {
    auto texture = std::make_unique<Texture>();
    job.converted = decoded_ ? decoded_->find(job.key) : nullptr;
    if (job.converted) {
      texture->size_levels(job.converted->width, job.converted->height);
    } else {
      try {  // a header that cannot be read sizes the texture 0 x 0: its level 0 is kept
        const ImageHeader header = read_image_header(job.bytes);
        texture->size_levels(header.width, header.height);
      } catch (const std::exception&) {
      }
    }
    scene.textures.push_back(std::move(texture));
  }
  for (auto& [slot, job] : pending_) slot->texture = scene.textures[job].get();
}

bool TextureLoader::has_unloaded() const {
  return std::any_of(jobs_.begin(), jobs_.end(), [](const Job& job) { return !job.loaded; });
}

void TextureLoader::clear_slots_of(size_t job) {
  for (auto& [slot, of] : pending_)
    if (of == job) slot->texture = nullptr;
}

void TextureLoader::load(Scene& scene, std::span<const int> first_levels) {
  std::vector<std::pair<size_t, int>> now;  // (job, first level)
  for (size_t i = 0; i < jobs_.size(); ++i) {
    const int first = i < first_levels.size() ? first_levels[i] : 0;
    if (jobs_[i].loaded || first == kNotYet) continue;
    jobs_[i].loaded = true;
    if (first >= kUnsampled) {
      clear_slots_of(i);
      jobs_[i].converted.reset();
    } else {
      now.emplace_back(i, first);
    }
  }
  std::vector<std::string> errors(now.size());
  std::atomic<int> handed_over = 0, decoded = 0;
  parallel_for(0, static_cast<std::int64_t>(now.size()), [&](std::int64_t n) {
    const auto [i, first] = now[static_cast<size_t>(n)];
    Job& job = jobs_[i];
    Texture& texture = *scene.textures[i];
    try {
      std::shared_ptr<const Pixels> pixels = std::move(job.converted);
      const bool from_conversion = pixels != nullptr;
      if (!from_conversion) pixels = std::make_shared<const Pixels>(decode_image(job.bytes, job.name));
      // Levels chosen on the header's size hold for these pixels only if they have that size.
      const bool sized_as_read = pixels->width == texture.width && pixels->height == texture.height;
      texture.build_levels(*pixels, sized_as_read ? first : 0);
      ++(from_conversion ? handed_over : decoded);  // counted once the texture stands
    } catch (const std::exception& e) {
      errors[static_cast<size_t>(n)] = e.what();
    }
  });
  for (size_t n = 0; n < now.size(); ++n)
    if (!errors[n].empty()) {
      scene.stats.warnings.push_back(errors[n] + " (drawn without this texture)");
      clear_slots_of(now[n].first);
    }
  scene.stats.textures_from_conversion += handed_over;
  scene.stats.textures_decoded += decoded;
}

void read_materials(const Asset& original, const Asset& converted, Scene& scene, TextureLoader& loader) {
  const auto& originals = original.model.materials;
  const auto& converteds = converted.model.materials;
  scene.materials.resize(originals.size() + 1);  // + the default material (section 3.9.6)
  for (size_t i = 0; i < originals.size(); ++i) {
    const tinygltf::Material& o = originals[i];
    const tinygltf::Material& c = i < converteds.size() ? converteds[i] : o;
    PreviewMaterial& m = scene.materials[i];
    m.name = o.name;
    m.alpha_mode = c.alphaMode == "MASK"    ? AlphaMode::Mask
                   : c.alphaMode == "BLEND" ? AlphaMode::Blend
                                            : AlphaMode::Opaque;
    m.alpha_cutoff = static_cast<float>(c.alphaCutoff);
    m.double_sided = o.doubleSided;
    if (o.normalTexture.index >= 0) {
      loader.request(original, o.normalTexture.index, o.normalTexture.texCoord, o.normalTexture.extensions, false,
                     m.normal_texture);
      m.normal_scale = static_cast<float>(o.normalTexture.scale);
    }
    if (o.occlusionTexture.index >= 0) {
      loader.request(original, o.occlusionTexture.index, o.occlusionTexture.texCoord, o.occlusionTexture.extensions,
                     false, m.occlusion_texture);
      m.occlusion_strength = static_cast<float>(o.occlusionTexture.strength);
      scene.stats.uses_occlusion = true;
    }
    if (o.emissiveFactor.size() == 3)
      m.emissive_factor = glm::vec3(o.emissiveFactor[0], o.emissiveFactor[1], o.emissiveFactor[2]);
    if (auto it = o.extensions.find("KHR_materials_emissive_strength"); it != o.extensions.end())
      if (it->second.Has("emissiveStrength"))
        m.emissive_factor *= static_cast<float>(it->second.Get("emissiveStrength").GetNumberAsDouble());
    if (m.emissive_factor != glm::vec3(0.0f)) {
      if (o.emissiveTexture.index >= 0)
        loader.request(original, o.emissiveTexture.index, o.emissiveTexture.texCoord, o.emissiveTexture.extensions,
                       true, m.emissive_texture);
      scene.stats.uses_emission = true;
    }
    auto read_metal_rough = [&](const Asset& asset, const tinygltf::Material& source, glm::vec4& base,
                                TextureSlot& base_slot, float& metallic, float& roughness, TextureSlot& mr_slot) {
      const auto& pbr = source.pbrMetallicRoughness;
      base = vec4_or(pbr.baseColorFactor, glm::vec4(1.0f));
      metallic = static_cast<float>(pbr.metallicFactor);
      roughness = static_cast<float>(pbr.roughnessFactor);
      if (pbr.baseColorTexture.index >= 0)
        loader.request(asset, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                       pbr.baseColorTexture.extensions, true, base_slot);
      if (pbr.metallicRoughnessTexture.index >= 0)
        loader.request(asset, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                       pbr.metallicRoughnessTexture.extensions, false, mr_slot);
    };
    read_metal_rough(converted, c, m.base_color_factor, m.base_color_texture, m.metallic_factor, m.roughness_factor,
                     m.metallic_roughness_texture);
    if (auto it = o.extensions.find(kSpecGloss); it != o.extensions.end()) {
      const LegacyMaterial legacy = read_legacy_material(original, static_cast<int>(i));
      m.has_spec_gloss = true;
      m.diffuse_factor = legacy.diffuse_factor;
      m.specular_factor = legacy.specular_factor;
      m.glossiness_factor = legacy.glossiness_factor;
      if (legacy.diffuse_texture)
        loader.request(original, legacy.diffuse_texture->index, legacy.diffuse_texture->texCoord,
                       legacy.diffuse_texture->extensions, true, m.diffuse_texture);
      if (legacy.spec_gloss_texture)
        loader.request(original, legacy.spec_gloss_texture->index, legacy.spec_gloss_texture->texCoord,
                       legacy.spec_gloss_texture->extensions, true, m.spec_gloss_texture);
    } else {
      read_metal_rough(original, o, m.original_base_color_factor, m.original_base_color_texture,
                       m.original_metallic_factor, m.original_roughness_factor, m.original_metallic_roughness_texture);
    }
  }
  // Default material: glTF 2.0 section 3.9.6 (white, metallic 1, roughness 1, single-sided).
  PreviewMaterial& fallback = scene.materials.back();
  fallback.name = "(default)";
  fallback.original_base_color_factor = glm::vec4(1.0f);
}

}  // namespace gltf_pbr::preview
