// Flattening an Asset into world-space triangles and two-sided materials (see scene.hpp).
#include "preview/scene.hpp"

#include <atomic>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <map>

#include "converter/legacy_material.hpp"
#include "core/accessor.hpp"
#include "core/color.hpp"
#include "core/draco.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "core/parallel.hpp"

namespace gltf_pbr::preview {
namespace {

constexpr int kRepeat = 10497, kClampToEdge = 33071, kMirroredRepeat = 33648, kNearest = 9728;

// --- Accessors (glTF 2.0 section 3.6.2, read by core/accessor.hpp) ---

using AccessorData = AccessorValues<double>;

// An attribute accessor in doubles (positions go through the node transforms in double); NaN or
// Inf would reach the rasterizer, so they are bad input here.
AccessorData read_attribute(const Asset& asset, int index) {
  AccessorData data = read_accessor_or_throw(asset, index);
  for (double v : data.values)
    if (!std::isfinite(v))
      throw InputError(asset.path.string(), pointer("accessors", index), "accessor holds NaN or Inf");
  return data;
}

// --- Node transforms (glTF 2.0 section 3.5.3) ---

glm::dmat4 local_transform(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());
  glm::dmat4 m(1.0);
  if (node.translation.size() == 3)
    m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)
    m *= glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
  if (node.scale.size() == 3) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

// --- The pose the file stores (glTF 2.0 sections 3.7.2.2 and 3.7.3) ---

// World matrix of every node, drawn or not: a skin's joints may sit outside the drawn scene.
// A node in a loop or deeper than the visit limit keeps its local matrix.
std::vector<glm::dmat4> node_world_matrices(const tinygltf::Model& model) {
  const std::size_t count = model.nodes.size();
  std::vector<int> parent(count, -1);
  for (std::size_t i = 0; i < count; ++i)
    for (int child : model.nodes[i].children)
      if (child >= 0 && static_cast<std::size_t>(child) < count && parent[static_cast<std::size_t>(child)] < 0)
        parent[static_cast<std::size_t>(child)] = static_cast<int>(i);
  std::vector<glm::dmat4> world(count);
  for (std::size_t i = 0; i < count; ++i) {
    glm::dmat4 m = local_transform(model.nodes[i]);
    int up = parent[i];
    for (int depth = 0; up >= 0 && depth < 256; ++depth, up = parent[static_cast<std::size_t>(up)])
      m = local_transform(model.nodes[static_cast<std::size_t>(up)]) * m;
    world[i] = m;
  }
  return world;
}

// How a node deforms its mesh at rest: morph target weights (the node's, else the mesh's, else
// none) and, for a skinned mesh, one matrix per joint, world(joint) · inverseBindMatrix. When the
// joints are stored at their bind pose this draws the mesh as stored.
struct Deformation {
  std::vector<double> morph_weights;
  std::vector<glm::dmat4> joint_matrices;  // empty: not skinned
};

Deformation node_deformation(const Asset& asset, int node_index, const std::vector<glm::dmat4>& node_world) {
  const tinygltf::Model& model = asset.model;
  const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(node_index)];
  Deformation d;
  d.morph_weights = !node.weights.empty() ? node.weights : model.meshes[static_cast<std::size_t>(node.mesh)].weights;
  if (node.skin < 0) return d;
  if (static_cast<std::size_t>(node.skin) >= model.skins.size())
    throw InputError(asset.path.string(), pointer("nodes", node_index) + "/skin", "skin does not exist");
  const tinygltf::Skin& skin = model.skins[static_cast<std::size_t>(node.skin)];
  const std::string skin_pointer = pointer("skins", node.skin);
  AccessorData inverse_bind;
  if (skin.inverseBindMatrices >= 0) {
    inverse_bind = read_attribute(asset, skin.inverseBindMatrices);
    if (inverse_bind.components != 16 || inverse_bind.count() < skin.joints.size())
      throw InputError(asset.path.string(), skin_pointer + "/inverseBindMatrices",
                       "needs one MAT4 per joint (" + std::to_string(skin.joints.size()) + ")");
  }
  for (std::size_t j = 0; j < skin.joints.size(); ++j) {
    const int joint = skin.joints[j];
    if (joint < 0 || static_cast<std::size_t>(joint) >= node_world.size())
      throw InputError(asset.path.string(), skin_pointer + "/joints/" + std::to_string(j), "node does not exist");
    const glm::dmat4 bind =
        inverse_bind.values.empty() ? glm::dmat4(1.0) : glm::make_mat4(&inverse_bind.values[j * 16]);
    d.joint_matrices.push_back(node_world[static_cast<std::size_t>(joint)] * bind);
  }
  return d;
}

// Decodes each distinct image once (keyed by its encoded bytes), in parallel; an image the
// conversion already holds as pixels (`decoded`) is taken from there and not decoded again.
class TextureLoader {
 public:
  TextureLoader(Scene& scene, const DecodedImages* decoded) : scene_(scene), decoded_(decoded) {}

  // Fills `slot` from textureInfo fields; the texels arrive in finish().
  void request(const Asset& asset, int texture_index, int tex_coord, const tinygltf::ExtensionMap& extensions,
               bool srgb, TextureSlot& slot) {
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
    if (inserted) jobs_.push_back({bytes, key, asset.path.string() + pointer("images", texture.source)});
    pending_.push_back({&slot, it->second});
  }

  void finish() {
    std::vector<std::unique_ptr<Texture>> decoded(jobs_.size());
    std::vector<std::string> errors(jobs_.size());
    std::atomic<int> handed_over = 0;
    parallel_for(0, static_cast<std::int64_t>(jobs_.size()), [&](std::int64_t i) {
      const auto& job = jobs_[static_cast<size_t>(i)];
      try {
        std::shared_ptr<const Pixels> pixels = decoded_ ? decoded_->find(job.key) : nullptr;
        const bool from_conversion = pixels != nullptr;
        if (!from_conversion) pixels = std::make_shared<const Pixels>(decode_image(job.bytes, job.name));
        auto texture = std::make_unique<Texture>();
        texture->width = pixels->width;
        texture->height = pixels->height;
        texture->rgba = rgba8_of(*pixels);
        texture->build_mips();
        decoded[static_cast<size_t>(i)] = std::move(texture);
        handed_over += from_conversion;  // counted once the texture stands, so a failure counts nowhere
      } catch (const std::exception& e) {
        errors[static_cast<size_t>(i)] = e.what();
      }
    });
    for (const auto& error : errors)
      if (!error.empty()) scene_.stats.warnings.push_back(error + " (drawn without this texture)");
    std::vector<const Texture*> by_job(jobs_.size(), nullptr);
    for (size_t i = 0; i < decoded.size(); ++i)
      if (decoded[i]) {
        by_job[i] = decoded[i].get();
        scene_.textures.push_back(std::move(decoded[i]));
      }
    for (auto& [slot, job] : pending_) slot->texture = by_job[job];
    scene_.stats.textures_from_conversion = handed_over;
    scene_.stats.textures_decoded = static_cast<int>(scene_.textures.size()) - handed_over;
  }

 private:
  // 8-bit RGBA, grey expanded to RGB and a missing alpha opaque; 8-bit pixels are copied as they are.
  static TexelBytes rgba8_of(const Pixels& pixels) {
    const size_t count = static_cast<size_t>(pixels.width) * static_cast<size_t>(pixels.height);
    const size_t ch = static_cast<size_t>(pixels.channels);
    TexelBytes rgba(count * 4);
    auto channel = [&](size_t in) -> std::uint8_t {
      if (!pixels.bytes.empty()) return pixels.bytes[in];
      return static_cast<std::uint8_t>(std::clamp(pixels.value(in), 0.0f, 1.0f) * 255.0f + 0.5f);
    };
    for (size_t p = 0; p < count; ++p) {
      const size_t in = p * ch;
      std::uint8_t* out = rgba.data() + p * 4;
      if (ch <= 2) {
        out[0] = out[1] = out[2] = channel(in);
        out[3] = ch == 2 ? channel(in + 1) : 255;
      } else {
        out[0] = channel(in), out[1] = channel(in + 1), out[2] = channel(in + 2);
        out[3] = ch >= 4 ? channel(in + 3) : 255;
      }
    }
    return rgba;
  }

  struct Job {
    std::span<const std::uint8_t> bytes;
    ImageContentKey key;
    std::string name;
  };
  Scene& scene_;
  const DecodedImages* decoded_;
  std::map<ImageContentKey, size_t> job_of_key_;
  std::vector<Job> jobs_;
  std::vector<std::pair<TextureSlot*, size_t>> pending_;
};

glm::vec4 vec4_or(const std::vector<double>& v, glm::vec4 fallback) {
  return v.size() == 4 ? glm::vec4(v[0], v[1], v[2], v[3]) : fallback;
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
      const LegacyMaterial legacy = read_legacy_material(original, static_cast<int>(i), it->second);
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

// Per-vertex tangents from UV derivatives (Lengyel 2001, "Computing Tangent Space Basis Vectors
// for an Arbitrary Mesh"), orthogonalised against the normal. The spec asks for MikkTSpace
// (glTF 2.0 section 3.7.2.1); on smooth, well-mapped meshes the two agree closely.
void generate_tangents(Scene& scene, size_t first_vertex, size_t first_triangle, int tex_coord) {
  const size_t count = scene.vertices.size() - first_vertex;
  std::vector<glm::vec3> tangent_sum(count, glm::vec3(0.0f)), bitangent_sum(count, glm::vec3(0.0f));
  for (size_t t = first_triangle; t < scene.triangles.size(); ++t) {
    const auto& tri = scene.triangles[t];
    const Vertex& a = scene.vertices[tri.vertex[0]];
    const Vertex& b = scene.vertices[tri.vertex[1]];
    const Vertex& c = scene.vertices[tri.vertex[2]];
    const glm::vec3 e1 = b.position - a.position, e2 = c.position - a.position;
    const glm::vec2 d1 = b.uv[tex_coord] - a.uv[tex_coord], d2 = c.uv[tex_coord] - a.uv[tex_coord];
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (std::abs(det) < 1e-20f) continue;
    const float r = 1.0f / det;
    const glm::vec3 tangent = (e1 * d2.y - e2 * d1.y) * r;
    const glm::vec3 bitangent = (e2 * d1.x - e1 * d2.x) * r;
    if (!std::isfinite(tangent.x + tangent.y + tangent.z + bitangent.x + bitangent.y + bitangent.z)) continue;
    for (std::uint32_t v : tri.vertex) {
      tangent_sum[v - first_vertex] += tangent;
      bitangent_sum[v - first_vertex] += bitangent;
    }
  }
  for (size_t i = 0; i < count; ++i) {
    Vertex& v = scene.vertices[first_vertex + i];
    const glm::vec3 n = v.normal;
    glm::vec3 t = tangent_sum[i] - n * glm::dot(n, tangent_sum[i]);
    const float length = glm::length(t);
    if (!(length > 1e-20f)) continue;  // w stays 0: the normal map is skipped here
    t /= length;
    const float handedness = glm::dot(glm::cross(n, t), bitangent_sum[i]) < 0.0f ? -1.0f : 1.0f;
    v.tangent = glm::vec4(t, handedness);
  }
}

// Section 3.7.2.2: the rest shape is the base plus each target's deltas times its weight.
void apply_morph_targets(const Asset& asset, const tinygltf::Primitive& primitive, const std::vector<double>& weights,
                         std::map<std::string, AccessorData>& attributes, const std::string& primitive_pointer) {
  for (std::size_t t = 0; t < primitive.targets.size() && t < weights.size(); ++t) {
    if (weights[t] == 0.0) continue;
    for (const auto& [semantic, index] : primitive.targets[t]) {
      auto base = attributes.find(semantic);
      if (base == attributes.end() || (semantic != "POSITION" && semantic != "NORMAL" && semantic != "TANGENT"))
        continue;
      const AccessorData delta = read_attribute(asset, index);
      const std::size_t stride = static_cast<std::size_t>(base->second.components);
      if (delta.components != 3 || delta.count() != base->second.count() || stride < 3)
        throw InputError(asset.path.string(), primitive_pointer + "/targets/" + std::to_string(t) + "/" + semantic,
                         "does not match the base attribute");
      for (std::size_t v = 0; v < delta.count(); ++v)
        for (std::size_t c = 0; c < 3; ++c) base->second.values[v * stride + c] += weights[t] * delta.values[v * 3 + c];
    }
  }
}

// Section 3.7.3.3: a skinned vertex moves by the weighted sum of its joints' matrices, over every
// JOINTS_n/WEIGHTS_n set. Weights are renormalised (the validator reports sums off one); a
// vertex with no weight at all stays as stored.
std::vector<glm::dmat4> skinning_matrices(const std::map<std::string, AccessorData>& attributes,
                                          const std::vector<glm::dmat4>& joint_matrices, std::size_t vertex_count,
                                          const std::string& asset_path, const std::string& primitive_pointer) {
  std::vector<glm::dmat4> blended(vertex_count, glm::dmat4(0.0));
  std::vector<double> total(vertex_count, 0.0);
  for (int set = 0;; ++set) {
    auto joints = attributes.find("JOINTS_" + std::to_string(set));
    auto weights = attributes.find("WEIGHTS_" + std::to_string(set));
    if (joints == attributes.end() || weights == attributes.end()) break;
    if (joints->second.components != 4 || weights->second.components != 4)
      throw InputError(asset_path, primitive_pointer + "/attributes/" + joints->first, "JOINTS and WEIGHTS are VEC4");
    for (std::size_t v = 0; v < vertex_count; ++v)
      for (std::size_t c = 0; c < 4; ++c) {
        const double weight = weights->second.values[v * 4 + c];
        if (weight == 0.0) continue;
        const double joint = joints->second.values[v * 4 + c];
        if (!(joint >= 0 && joint < static_cast<double>(joint_matrices.size())))
          throw InputError(asset_path, primitive_pointer + "/attributes/" + joints->first,
                           "joint " + std::to_string(static_cast<long long>(joint)) + " of vertex " +
                               std::to_string(v) + " is not in the skin");
        blended[v] += weight * joint_matrices[static_cast<std::size_t>(joint)];
        total[v] += weight;
      }
  }
  for (std::size_t v = 0; v < vertex_count; ++v) blended[v] = total[v] > 0.0 ? blended[v] / total[v] : glm::dmat4(1.0);
  return blended;
}

void add_primitive(const Asset& asset, int mesh_index, int primitive_index, const glm::dmat4& world,
                   const Deformation& deformation, Scene& scene) {
  const tinygltf::Primitive& primitive =
      asset.model.meshes[static_cast<size_t>(mesh_index)].primitives[static_cast<size_t>(primitive_index)];
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    ++scene.stats.skipped_primitives;  // points and lines have no surface to shade
    return;
  }
  std::map<std::string, AccessorData> attributes;
  std::vector<std::uint32_t> indices;
  bool has_indices = false;
  if (primitive.extensions.count("KHR_draco_mesh_compression")) {
    DecodedPrimitive decoded = decode_draco_primitive(asset, mesh_index, primitive_index);
    ++scene.stats.draco_primitives;
    for (auto& [semantic, values] : decoded.attributes) {
      AccessorData data;
      data.components = decoded.components[semantic];
      if (data.components <= 0) continue;
      data.values.assign(values.begin(), values.end());
      attributes[semantic] = std::move(data);
    }
    indices = std::move(decoded.indices);
    has_indices = true;
  } else {
    for (const auto& [semantic, index] : primitive.attributes) {
      const bool drawn = semantic == "POSITION" || semantic == "NORMAL" || semantic == "TANGENT" ||
                         semantic == "TEXCOORD_0" || semantic == "TEXCOORD_1" || semantic == "COLOR_0";
      const bool skinning =
          !deformation.joint_matrices.empty() && (semantic.starts_with("JOINTS_") || semantic.starts_with("WEIGHTS_"));
      if (drawn || skinning) attributes[semantic] = read_attribute(asset, index);
    }
    if (primitive.indices >= 0) {
      indices = read_index_accessor_or_throw(asset, primitive.indices);
      has_indices = true;
    }
  }
  auto position_it = attributes.find("POSITION");
  if (position_it == attributes.end() || position_it->second.components != 3) {
    ++scene.stats.skipped_primitives;
    return;
  }
  const size_t vertex_count = position_it->second.count();
  for (auto& [semantic, data] : attributes)
    if (data.count() < vertex_count)
      throw InputError(asset.path.string(),
                       "/meshes/" + std::to_string(mesh_index) + "/primitives/" + std::to_string(primitive_index) +
                           "/attributes/" + semantic,
                       "has fewer elements than POSITION");
  if (!has_indices) {
    indices.resize(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i) indices[i] = static_cast<std::uint32_t>(i);
  }
  for (std::uint32_t index : indices)
    if (index >= vertex_count)
      throw InputError(
          asset.path.string(),
          "/meshes/" + std::to_string(mesh_index) + "/primitives/" + std::to_string(primitive_index) + "/indices",
          "index " + std::to_string(index) + " is past the last vertex");

  const std::string primitive_pointer =
      "/meshes/" + std::to_string(mesh_index) + "/primitives/" + std::to_string(primitive_index);
  apply_morph_targets(asset, primitive, deformation.morph_weights, attributes, primitive_pointer);
  // Section 3.7.3.3: a skinned mesh ignores its node's transform; its joints place it.
  const bool skinned = !deformation.joint_matrices.empty();
  const std::vector<glm::dmat4> skinning = skinned
                                               ? skinning_matrices(attributes, deformation.joint_matrices, vertex_count,
                                                                   asset.path.string(), primitive_pointer)
                                               : std::vector<glm::dmat4>{};
  if (skinned) ++scene.stats.skinned_primitives;
  if (!primitive.targets.empty()) ++scene.stats.morphed_primitives;
  const glm::dmat3 node_normal_matrix = glm::inverseTranspose(glm::dmat3(world));
  const glm::dmat4& winding_matrix = skinned ? deformation.joint_matrices.front() : world;
  const bool mirrored = glm::determinant(glm::dmat3(winding_matrix)) < 0.0;  // section 3.7.4: flips winding
  const size_t first_vertex = scene.vertices.size();
  const size_t first_triangle = scene.triangles.size();
  auto get = [&](const char* semantic) -> const AccessorData* {
    auto it = attributes.find(semantic);
    return it == attributes.end() ? nullptr : &it->second;
  };
  const AccessorData* normals = get("NORMAL");
  const AccessorData* tangents = get("TANGENT");
  const AccessorData* uv_sets[2] = {get("TEXCOORD_0"), get("TEXCOORD_1")};
  const AccessorData* colors = get("COLOR_0");
  for (size_t i = 0; i < vertex_count; ++i) {
    Vertex v;
    const glm::dmat4& to_world = skinned ? skinning[i] : world;
    const glm::dmat3 normal_matrix = skinned ? glm::inverseTranspose(glm::dmat3(to_world)) : node_normal_matrix;
    const double* p = position_it->second.values.data() + i * 3;
    const glm::dvec3 world_position = glm::dvec3(to_world * glm::dvec4(p[0], p[1], p[2], 1.0));
    v.position = glm::vec3(world_position);
    scene.bounds.add(world_position);
    if (normals && normals->components == 3) {
      const double* n = normals->values.data() + i * 3;
      const glm::dvec3 wn = normal_matrix * glm::dvec3(n[0], n[1], n[2]);
      const double length = glm::length(wn);
      if (length > 0.0) v.normal = glm::vec3(wn / length);
    }
    if (tangents && tangents->components == 4) {
      const double* t = tangents->values.data() + i * 4;
      const glm::dvec3 wt = glm::dmat3(to_world) * glm::dvec3(t[0], t[1], t[2]);
      const double length = glm::length(wt);
      if (length > 0.0)
        v.tangent =
            glm::vec4(glm::vec3(wt / length), static_cast<float>(t[3] < 0 ? -1 : 1) * (mirrored ? -1.0f : 1.0f));
    }
    for (int set = 0; set < 2; ++set)
      if (uv_sets[set] && uv_sets[set]->components == 2)
        v.uv[set] = glm::vec2(uv_sets[set]->values[i * 2], uv_sets[set]->values[i * 2 + 1]);
    if (colors && (colors->components == 3 || colors->components == 4)) {
      const double* c = colors->values.data() + i * static_cast<size_t>(colors->components);
      v.color = glm::vec4(c[0], c[1], c[2], colors->components == 4 ? c[3] : 1.0);
    }
    scene.vertices.push_back(v);
  }
  const std::int32_t material =
      primitive.material >= 0 && primitive.material < static_cast<int>(scene.materials.size()) - 1
          ? primitive.material
          : static_cast<std::int32_t>(scene.materials.size() - 1);
  auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (a == b || b == c || a == c) return;
    const auto base = static_cast<std::uint32_t>(first_vertex);
    if (mirrored) std::swap(b, c);
    scene.triangles.push_back({{base + a, base + b, base + c}, material});
  };
  // Section 3.7.2.1: strips alternate winding; fans share the first vertex.
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t i = 0; i + 2 < indices.size(); i += 3) emit(indices[i], indices[i + 1], indices[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < indices.size(); ++i)
      if (i % 2 == 0)
        emit(indices[i], indices[i + 1], indices[i + 2]);
      else
        emit(indices[i + 1], indices[i], indices[i + 2]);
  } else {
    for (size_t i = 1; i + 1 < indices.size(); ++i) emit(indices[0], indices[i], indices[i + 1]);
  }
  const bool has_normal_map = static_cast<size_t>(material) < asset.model.materials.size() &&
                              asset.model.materials[static_cast<size_t>(material)].normalTexture.index >= 0;
  if (has_normal_map && !tangents && normals)
    generate_tangents(scene, first_vertex, first_triangle,
                      scene.materials[static_cast<size_t>(material)].normal_texture.tex_coord);
  ++scene.stats.meshes_drawn;
}

void visit_node(const Asset& asset, int node_index, const glm::dmat4& parent, const std::vector<glm::dmat4>& node_world,
                Scene& scene, int depth) {
  const auto& nodes = asset.model.nodes;
  if (node_index < 0 || node_index >= static_cast<int>(nodes.size()) || depth > 256) return;
  const tinygltf::Node& node = nodes[static_cast<size_t>(node_index)];
  const glm::dmat4 world = parent * local_transform(node);
  // Skins and morph targets are drawn at rest: no animation, the pose the nodes and weights store.
  if (node.mesh >= 0 && node.mesh < static_cast<int>(asset.model.meshes.size())) {
    const Deformation deformation = node_deformation(asset, node_index, node_world);
    for (size_t p = 0; p < asset.model.meshes[static_cast<size_t>(node.mesh)].primitives.size(); ++p)
      add_primitive(asset, node.mesh, static_cast<int>(p), world, deformation, scene);
  }
  if (node.camera >= 0 && node.camera < static_cast<int>(asset.model.cameras.size())) {
    const tinygltf::Camera& camera = asset.model.cameras[static_cast<size_t>(node.camera)];
    if (camera.type == "perspective") {
      SceneCamera c;
      c.camera_to_world = world;
      c.yfov = static_cast<float>(camera.perspective.yfov);
      c.znear = static_cast<float>(camera.perspective.znear);
      if (camera.perspective.zfar > 0) c.zfar = static_cast<float>(camera.perspective.zfar);
      scene.cameras.push_back(c);
    }
  }
  for (int child : node.children) visit_node(asset, child, world, node_world, scene, depth + 1);
}

float wrap_coordinate(float t, int mode) {
  if (mode == kClampToEdge) return std::clamp(t, 0.0f, 1.0f);
  if (mode == kMirroredRepeat) {
    const float period = t - 2.0f * std::floor(t * 0.5f);
    return period > 1.0f ? 2.0f - period : period;
  }
  return t - std::floor(t);
}

// Texel index for bilinear taps. wrap_coordinate has already folded the coordinate into
// [0, 1], so taps fall in [-1, size] and one comparison wraps them (no integer division).
int wrap_texel(int i, int size, int mode) {
  if (i < 0) return mode == kRepeat ? i + size : 0;
  if (i >= size) return mode == kRepeat ? i - size : size - 1;
  return i;
}

}  // namespace

void Texture::build_mips() {
  mips.clear();
  int w = width, h = height;
  const TexelBytes* source = &rgba;
  while (w > 1 || h > 1) {
    TextureLevel level{std::max(1, w / 2), std::max(1, h / 2), {}};
    level.rgba.resize(static_cast<size_t>(level.width) * static_cast<size_t>(level.height) * 4);
    std::uint8_t* out = level.rgba.data();
    for (int y = 0; y < level.height; ++y) {  // a 2 x 2 box; an odd last row or column repeats
      const size_t row0 = static_cast<size_t>(std::min(2 * y, h - 1)) * static_cast<size_t>(w);
      const size_t row1 = static_cast<size_t>(std::min(2 * y + 1, h - 1)) * static_cast<size_t>(w);
      for (int x = 0; x < level.width; ++x, out += 4) {
        const size_t x0 = static_cast<size_t>(std::min(2 * x, w - 1)),
                     x1 = static_cast<size_t>(std::min(2 * x + 1, w - 1));
        const std::uint8_t *a = &(*source)[(row0 + x0) * 4], *b = &(*source)[(row0 + x1) * 4];
        const std::uint8_t *c = &(*source)[(row1 + x0) * 4], *d = &(*source)[(row1 + x1) * 4];
        for (int k = 0; k < 4; ++k) out[k] = static_cast<std::uint8_t>((a[k] + b[k] + c[k] + d[k] + 2) / 4);
      }
    }
    mips.push_back(std::move(level));
    w = mips.back().width, h = mips.back().height;
    source = &mips.back().rgba;
  }
}

namespace {

[[gnu::always_inline]] inline glm::vec4 decode_texel(const std::uint8_t* t, const float* srgb_lut) {
  if (srgb_lut) return {srgb_lut[t[0]], srgb_lut[t[1]], srgb_lut[t[2]], static_cast<float>(t[3]) * (1.0f / 255.0f)};
  return glm::vec4(t[0], t[1], t[2], t[3]) * (1.0f / 255.0f);
}

glm::vec4 sample_level(const TextureSlot& slot, const std::uint8_t* texels, int width, int height, glm::vec2 uv) {
  static const float* const srgb_lut = srgb8_to_linear_table().data();
  const float* lut = slot.srgb ? srgb_lut : nullptr;
  const float u = wrap_coordinate(uv.x, slot.wrap_s) * static_cast<float>(width) - 0.5f;
  const float v = wrap_coordinate(uv.y, slot.wrap_t) * static_cast<float>(height) - 0.5f;
  const size_t stride = static_cast<size_t>(width) * 4;
  if (slot.nearest) {
    const int x = wrap_texel(static_cast<int>(std::floor(u + 0.5f)), width, slot.wrap_s);
    const int y = wrap_texel(static_cast<int>(std::floor(v + 0.5f)), height, slot.wrap_t);
    return decode_texel(texels + static_cast<size_t>(y) * stride + static_cast<size_t>(x) * 4, lut);
  }
  const float fx = std::floor(u), fy = std::floor(v);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const float tx = u - fx, ty = v - fy;
  const size_t column0 = static_cast<size_t>(wrap_texel(x0, width, slot.wrap_s)) * 4;
  const size_t column1 = static_cast<size_t>(wrap_texel(x0 + 1, width, slot.wrap_s)) * 4;
  const std::uint8_t* row0 = texels + static_cast<size_t>(wrap_texel(y0, height, slot.wrap_t)) * stride;
  const std::uint8_t* row1 = texels + static_cast<size_t>(wrap_texel(y0 + 1, height, slot.wrap_t)) * stride;
  const glm::vec4 top = glm::mix(decode_texel(row0 + column0, lut), decode_texel(row0 + column1, lut), tx);
  const glm::vec4 bottom = glm::mix(decode_texel(row1 + column0, lut), decode_texel(row1 + column1, lut), tx);
  return glm::mix(top, bottom, ty);
}

}  // namespace

SlotLookup slot_lookup(const TextureSlot& slot, const glm::vec2 uv_sets[2], const UvDerivatives* derivatives) {
  const Texture& texture = *slot.texture;
  SlotLookup lookup{uv_sets[slot.tex_coord]};
  auto transform_linear = [&](glm::vec2 d) {
    return slot.has_transform
               ? glm::vec2(slot.row_u.x * d.x + slot.row_u.y * d.y, slot.row_v.x * d.x + slot.row_v.y * d.y)
               : d;
  };
  glm::vec2& uv = lookup.uv;
  if (slot.has_transform)  // rows of the affine matrix
    uv = glm::vec2(slot.row_u.x * uv.x + slot.row_u.y * uv.y + slot.row_u.z,
                   slot.row_v.x * uv.x + slot.row_v.y * uv.y + slot.row_v.z);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
  if (derivatives && !texture.mips.empty()) {
    const glm::vec2 size(static_cast<float>(texture.width), static_cast<float>(texture.height));
    const glm::vec2 dx = transform_linear(derivatives->dx[slot.tex_coord]) * size;
    const glm::vec2 dy = transform_linear(derivatives->dy[slot.tex_coord]) * size;
    const float rho2 = std::max(dx.x * dx.x + dx.y * dx.y, dy.x * dy.x + dy.y * dy.y);
    if (rho2 > 1.0f && std::isfinite(rho2))
      lookup.lod = std::min(0.5f * std::log2(rho2), static_cast<float>(texture.mips.size()));
  }
  return lookup;
}

glm::vec4 sample(const TextureSlot& slot, const glm::vec2 uv_sets[2], const UvDerivatives* derivatives) {
  const Texture& texture = *slot.texture;
  const SlotLookup lookup = slot_lookup(slot, uv_sets, derivatives);
  const glm::vec2 uv = lookup.uv;  // named, not a structured binding: clang 14 lambdas cannot capture those
  const float lod = lookup.lod;
  auto level = [&](int l) {
    if (l == 0) return sample_level(slot, texture.rgba.data(), texture.width, texture.height, uv);
    const TextureLevel& m = texture.mips[static_cast<size_t>(l - 1)];
    return sample_level(slot, m.rgba.data(), m.width, m.height, uv);
  };
  const int l0 = static_cast<int>(lod);
  const float t = lod - static_cast<float>(l0);
  const glm::vec4 a = level(l0);
  return t > 0.0f && l0 < static_cast<int>(texture.mips.size()) ? glm::mix(a, level(l0 + 1), t) : a;
}

Scene build_scene(const Asset& original, const Asset& converted, const DecodedImages* decoded) {
  Scene scene;
  TextureLoader loader(scene, decoded);
  read_materials(original, converted, scene, loader);
  const auto& model = original.model;
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int s =
        model.defaultScene >= 0 && model.defaultScene < static_cast<int>(model.scenes.size()) ? model.defaultScene : 0;
    roots = model.scenes[static_cast<size_t>(s)].nodes;
  } else {  // no scene: every node that is nobody's child
    std::vector<bool> is_child(model.nodes.size(), false);
    for (const auto& node : model.nodes)
      for (int c : node.children)
        if (c >= 0 && c < static_cast<int>(is_child.size())) is_child[static_cast<size_t>(c)] = true;
    for (size_t i = 0; i < model.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
  }
  const std::vector<glm::dmat4> node_world = node_world_matrices(model);
  for (int root : roots) visit_node(original, root, glm::dmat4(1.0), node_world, scene, 0);
  loader.finish();
  scene.stats.triangles = static_cast<long long>(scene.triangles.size());
  scene.stats.vertices = static_cast<long long>(scene.vertices.size());
  return scene;
}

}  // namespace gltf_pbr::preview

namespace gltf_pbr::preview {

SurfacePoint interpolate(const Scene& scene, std::uint32_t triangle, glm::vec3 b) {
  const Triangle& t = scene.triangles[triangle];
  const Vertex& v0 = scene.vertices[t.vertex[0]];
  const Vertex& v1 = scene.vertices[t.vertex[1]];
  const Vertex& v2 = scene.vertices[t.vertex[2]];
  SurfacePoint p;
  p.normal = v0.normal * b.x + v1.normal * b.y + v2.normal * b.z;
  p.face_normal = glm::cross(v1.position - v0.position, v2.position - v0.position);
  p.tangent = v0.tangent * b.x + v1.tangent * b.y + v2.tangent * b.z;
  for (int s = 0; s < 2; ++s) p.uv[s] = v0.uv[s] * b.x + v1.uv[s] * b.y + v2.uv[s] * b.z;
  p.color = v0.color * b.x + v1.color * b.y + v2.color * b.z;
  return p;
}

float surface_alpha(const Scene&, const PreviewMaterial& material, const SurfacePoint& point) {
  float alpha = material.base_color_factor.a * point.color.a;
  if (material.base_color_texture) alpha *= sample(material.base_color_texture, point.uv).a;
  return alpha;
}

}  // namespace gltf_pbr::preview
