// Image resources (glTF 2.0 spec 3.8.2 "Images"): the bytes must be the declared format, PNG or
// JPEG in core glTF, WebP or KTX2 with their extensions, and readable far enough to know their size.
#pragma once
#include "validators/structure/structure_internal.hpp"

namespace gltf_pbr::structure {

void check_images(Context& context);  // images.cpp
// TEXTURE_INVALID_IMAGE_MIME_TYPE, once the images are read (images.cpp).
void check_texture_sources(Context& context);
// How materials use an image: the pointer of the first textureInfo that reads it as colour data,
// the first that reads it as non-colour data, and the first texture that minifies it with mipmaps;
// "" where none does.
struct ImageUse {
  std::string colour, non_colour, mipmapped;
};
// What a KTX2 file's container (KTX2_INVALID_CONTAINER), KHR_texture_basisu's rules for it and its
// use (KTX2_BASISU_MISMATCH) or the extension's advice on mipmaps (KTX2_MIPMAPS_INCOMPLETE) find
// wrong, each with its reason; ktx2.cpp.
struct Ktx2Finding {
  const char* code;
  std::string reason;
};
std::vector<Ktx2Finding> check_ktx2(std::span<const std::uint8_t> bytes, const ImageUse& use);
void check_draco(Context& context);  // draco.cpp: KHR_draco_mesh_compression data
void decode_meshopt_views(Context& context);  // meshopt.cpp: EXT_meshopt_compression data

}  // namespace gltf_pbr::structure
