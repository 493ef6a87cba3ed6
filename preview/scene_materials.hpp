// The materials of the scene, read twice (the legacy "before" side and the converted "after" side),
// and the textures they name, each distinct image decoded once.
#pragma once
#include <map>
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
class TextureLoader {
 public:
  TextureLoader(Scene& scene, const DecodedImages* decoded) : scene_(scene), decoded_(decoded) {}

  // Fills `slot` from textureInfo fields (sampler, texCoord, KHR_texture_transform); the texels
  // arrive in finish().
  void request(const Asset& asset, int texture_index, int tex_coord, const tinygltf::ExtensionMap& extensions,
               bool srgb, TextureSlot& slot);
  // Decodes what was requested, in parallel, and points every requested slot at its texture; an
  // image that cannot be decoded is a warning in scene.stats and its slots stay empty.
  void finish();

 private:
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

// Fills scene.materials from the original's materials (legacy side) and the conversion's (core
// side), with the default material last (glTF 2.0 section 3.9.6); textures go through `loader`.
void read_materials(const Asset& original, const Asset& converted, Scene& scene, TextureLoader& loader);

}  // namespace gltf_pbr::preview
