// The materials of the scene, read twice (the legacy "before" side and the converted "after" side),
// and the textures they name, each distinct image decoded once.
#pragma once
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/asset.hpp"
#include "core/image.hpp"
#include "preview/scene.hpp"

namespace gltf_pbr::preview {

// Decodes each distinct image once (keyed by its encoded bytes), in parallel; an image the
// conversion already holds as pixels (`decoded`) is taken from there and not decoded again.
// Texture i of scene.textures is the i-th distinct image requested.
class TextureLoader {
 public:
  explicit TextureLoader(const DecodedImages* decoded) : decoded_(decoded) {}

  // Fills `slot` from textureInfo fields (sampler, texCoord, KHR_texture_transform); the slot
  // points at its texture after prepare().
  void request(const Asset& asset, int texture_index, int tex_coord, const tinygltf::ExtensionMap& extensions,
               bool srgb, TextureSlot& slot);
  // One texture per distinct image, sized (from the conversion's pixels or the image header)
  // but without texels, and every requested slot pointed at its texture.
  void prepare(Scene& scene);
  // Makes the texels of texture i from level first_levels[i] down; kUnsampled leaves it without
  // texels and empties its slots (nothing samples it); kNotYet leaves it for a later load. A
  // texture made before is not made again. An image that cannot be decoded is a warning in
  // scene.stats and its slots become empty.
  static constexpr int kNotYet = -1;
  void load(Scene& scene, std::span<const int> first_levels);
  bool has_unloaded() const;

 private:
  struct Job {
    std::span<const std::uint8_t> bytes;
    ImageContentKey key;
    std::string name;
    std::shared_ptr<const Pixels> converted;  // the conversion's pixels, until the texture is made
    bool loaded = false;
  };
  void clear_slots_of(size_t job);
  const DecodedImages* decoded_;
  std::map<ImageContentKey, size_t> job_of_key_;
  std::vector<Job> jobs_;
  std::vector<std::pair<TextureSlot*, size_t>> pending_;
};

// Fills scene.materials from the original's materials (legacy side) and the conversion's (core
// side), with the default material last (glTF 2.0 section 3.9.6); textures go through `loader`.
void read_materials(const Asset& original, const Asset& converted, Scene& scene, TextureLoader& loader);

}  // namespace gltf_pbr::preview
