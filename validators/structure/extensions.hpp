// Extension objects (glTF 2.0 spec 3.12 "Extensions"): where each known extension may appear, its
// schema, and the checks its specification asks for.
#pragma once
#include <functional>

#include "validators/structure/schema_reader.hpp"

namespace gltf_pbr::structure {

// The kind of object an "extensions" property belongs to.
enum class Owner {
  Root,
  Asset,
  Accessor,
  Animation,
  ChannelTarget,
  Buffer,
  BufferView,
  Camera,
  Image,
  Material,
  Mesh,
  Primitive,
  Node,
  Sampler,
  Scene,
  Skin,
  Texture,
  TextureInfo,
  Other
};

// What the extension readers need from the schema walk: the model of the object being read, and
// a way to read a textureInfo into the current material's texture bindings.
struct ExtensionHooks {
  // kind: 0 textureInfo, 1 normalTextureInfo (with scale), 2 occlusionTextureInfo (with strength)
  std::function<void(const Json& owner, const std::string& pointer, std::string_view key, int kind)> texture_info;
  std::function<MaterialModel*()> material;
  std::function<PrimitiveModel*()> primitive;
  std::function<NodeModel*()> node;
  std::function<TextureModel*()> texture;
  std::function<BufferModel*()> buffer;
  std::function<BufferViewModel*()> buffer_view;
};

bool extension_supported(const std::string& name);
void read_extensions(SchemaReader& read, const Json& object, const std::string& pointer, Owner owner,
                     const ExtensionHooks& hooks);

}  // namespace gltf_pbr::structure
