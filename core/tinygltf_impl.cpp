// The one translation unit that compiles tinygltf (see CMakeLists.txt for why).
#define TINYGLTF_IMPLEMENTATION
// Image files are mapped by load_asset, not read and copied by tinygltf (core/asset.hpp).
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
