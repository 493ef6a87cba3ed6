// The asset flattened for drawing: world-space triangles of every mesh under the scene's node
// transforms, and each material read twice, as the legacy spec-gloss side ("before") and as the
// converted albedo + metalness side ("after"). Textures are decoded here, once per distinct image:
// at once, or (a render) after the raster, from the finest mip level its pixels sample.
#pragma once
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/asset.hpp"
#include "core/image.hpp"  // DecodedImages, TexelBytes

namespace gltf_pbr::preview {

class TextureLoader;  // scene_materials.hpp

// Decoded texels, 8 bits per channel, always RGBA (glTF images are at most 8 bits in practice;
// 16-bit PNGs are quantised, which a preview can afford), with a box-filtered mip chain:
// minified textures would otherwise alias into noise that the difference map reports as error.
// (TexelBytes: filled right after allocation, so not zeroed first.)
struct TextureLevel {
  int width = 0, height = 0;
  TexelBytes rgba;
};
// A preview keeps only the levels its pixels sample (first_level and down, see
// finest_sampled_levels in gbuffer.hpp): the levels above have their sizes and no texels.
struct Texture {
  int width = 0, height = 0;
  TexelBytes rgba;                 // level 0; empty when first_level > 0
  std::vector<TextureLevel> mips;  // level 1, 2, ... down to 1 x 1
  int first_level = 0;
  void build_mips();  // from rgba
  // Levels first_level and down from `source`, read as 8-bit RGBA (grey expanded to RGB, a
  // missing alpha opaque, wider samples rounded); the levels above are computed only as steps to
  // the next, and not kept.
  void build_levels(const Pixels& source, int first_level);
  void size_levels(int level0_width, int level0_height);  // every level's size, no texels
};

// A material's reference to a texture (glTF 2.0 section 5.19 textureInfo, KHR_texture_transform).
struct TextureSlot {
  const Texture* texture = nullptr;
  int tex_coord = 0;
  bool srgb = false;                   // RGB decoded from sRGB (alpha stays linear)
  int wrap_s = 10497, wrap_t = 10497;  // glTF 2.0 section 5.26 sampler wrap modes (REPEAT default)
  bool nearest = false;                // magFilter NEAREST
  bool has_transform = false;
  // KHR_texture_transform: uv' = T * R * S * uv, as two rows of an affine 2x3 matrix.
  glm::vec3 row_u{1, 0, 0}, row_v{0, 1, 0};
  explicit operator bool() const { return texture != nullptr; }
};

// Screen-space derivatives of each texture-coordinate set (per pixel step in x and in y).
struct UvDerivatives {
  glm::vec2 dx[2]{}, dy[2]{};
};

// Where a slot reads: its texCoord set through KHR_texture_transform (uv' = T R S uv; a
// non-finite result reads (0, 0)), and the level of detail (OpenGL 4.6 section 8.14.1: log2 of
// rho, the longer derivative scaled to texels; 0 without derivatives or mips). One definition
// for `sample` and the G-buffer's footprints (texture_sampler.hpp).
struct SlotLookup {
  glm::vec2 uv{};
  float lod = 0.0f;
};
SlotLookup slot_lookup(const TextureSlot& slot, const glm::vec2 uv_sets[2], const UvDerivatives* derivatives);

// Trilinear (or nearest) sample with the sampler's wrap modes; RGB in linear space when `srgb`.
// The mip level follows the footprint (OpenGL 4.6 section 8.14.1, rho = max of the scaled
// derivative lengths); without derivatives, level 0 bilinear.
glm::vec4 sample(const TextureSlot& slot, const glm::vec2 uv_sets[2], const UvDerivatives* derivatives = nullptr);

enum class AlphaMode { Opaque, Mask, Blend };

struct PreviewMaterial {
  std::string name;
  AlphaMode alpha_mode = AlphaMode::Opaque;
  float alpha_cutoff = 0.5f;
  bool double_sided = false;
  // Shared by both sides (the conversion does not touch them).
  TextureSlot normal_texture;
  float normal_scale = 1.0f;
  TextureSlot occlusion_texture;
  float occlusion_strength = 1.0f;
  TextureSlot emissive_texture;
  glm::vec3 emissive_factor{0.0f};  // times KHR_materials_emissive_strength
  // "after": core pbrMetallicRoughness of the converted asset.
  glm::vec4 base_color_factor{1.0f};
  TextureSlot base_color_texture;
  float metallic_factor = 1.0f, roughness_factor = 1.0f;
  TextureSlot metallic_roughness_texture;
  // "before": the original's KHR_materials_pbrSpecularGlossiness; without it, the "before" side
  // is the original's own metal-rough material (through converter/solver.hpp to_spec_gloss).
  bool has_spec_gloss = false;
  glm::vec4 diffuse_factor{1.0f};
  TextureSlot diffuse_texture;
  glm::vec3 specular_factor{1.0f};
  float glossiness_factor = 1.0f;
  TextureSlot spec_gloss_texture;
  // Original metal-rough (the "before" side of a material without spec-gloss).
  glm::vec4 original_base_color_factor{1.0f};
  TextureSlot original_base_color_texture;
  float original_metallic_factor = 1.0f, original_roughness_factor = 1.0f;
  TextureSlot original_metallic_roughness_texture;
};

struct Vertex {
  glm::vec3 position{0.0f};  // world space
  glm::vec3 normal{0.0f};    // world space; zero: flat-shade (glTF 2.0 section 3.7.2.1)
  glm::vec4 tangent{0.0f};   // world xyz + handedness w; w == 0: none
  glm::vec2 uv[2]{};
  glm::vec4 color{1.0f};  // COLOR_0, linear
};

struct Triangle {
  std::uint32_t vertex[3];
  std::int32_t material;  // index into Scene::materials (the default material is appended last)
};

struct Bounds {
  glm::dvec3 min{1e300}, max{-1e300};
  bool empty() const { return min.x > max.x; }
  void add(glm::dvec3 p) { min = glm::min(min, p), max = glm::max(max, p); }
};

struct SceneCamera {  // a glTF perspective camera under its node transform
  int index = -1;     // into the document's cameras
  glm::dmat4 camera_to_world{1.0};
  float yfov = 0.8f, znear = 0.01f;
  std::optional<float> zfar;
};

struct SceneStats {
  long long triangles = 0, vertices = 0;
  int meshes_drawn = 0, draco_primitives = 0, skipped_primitives = 0, textures_decoded = 0;
  int textures_from_conversion = 0;                    // taken as pixels from the conversion: not decoded again
  int skinned_primitives = 0, morphed_primitives = 0;  // drawn at rest (no animation)
  bool uses_emission = false, uses_occlusion = false;
  std::vector<std::string> warnings;
};

struct Scene {
  std::vector<Vertex> vertices;
  std::vector<Triangle> triangles;
  std::vector<PreviewMaterial> materials;
  std::vector<std::unique_ptr<Texture>> textures;
  std::vector<SceneCamera> cameras;
  Bounds bounds;
  SceneStats stats;
  std::shared_ptr<TextureLoader> unloaded;  // TextureLoading::SampledLevelsLater: until load_textures
};

// When the textures' texels are made: at once, every level; or after the render has rasterized
// the scene and knows which levels its pixels sample (load_textures). The base colour textures
// of masked and blended materials are made at once either way: the rasterizer tests their alpha.
enum class TextureLoading { AllLevelsNow, SampledLevelsLater };

// `original` supplies geometry, shared material inputs and the "before" side; `converted` (the
// same asset after converter::convert, same material indices) supplies the "after" side.
// Images held in `decoded` (the conversion's, when it kept them) are not decoded again.
// Throws InputError for broken accessors and failing Draco data.
Scene build_scene(const Asset& original, const Asset& converted, const DecodedImages* decoded = nullptr,
                  TextureLoading loading = TextureLoading::AllLevelsNow);
// Makes the textures build_scene left for later, each from first_levels[i] down (i: its index
// in scene.textures; kUnsampled: no pixel samples it, so no texels at all).
inline constexpr int kUnsampled = 1 << 30;
void load_textures(Scene& scene, std::span<const int> first_levels);

}  // namespace gltf_pbr::preview

namespace gltf_pbr::preview {

// Attributes of a triangle at barycentric coordinates (weights of its three vertices).
struct SurfacePoint {
  glm::vec3 normal{0.0f};  // interpolated, unnormalised; zero when the mesh has no normals
  glm::vec3 face_normal{0.0f};
  glm::vec4 tangent{0.0f};
  glm::vec2 uv[2]{};
  glm::vec4 color{1.0f};
};
SurfacePoint interpolate(const Scene& scene, std::uint32_t triangle, glm::vec3 barycentric);

// Coverage alpha of the "after" material (baseColor alpha x COLOR_0 alpha); the conversion keeps
// the legacy diffuse alpha, so both sides share one coverage.
float surface_alpha(const Scene& scene, const PreviewMaterial& material, const SurfacePoint& point);

}  // namespace gltf_pbr::preview
