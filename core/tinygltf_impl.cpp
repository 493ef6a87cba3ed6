// The one translation unit that compiles tinygltf (see CMakeLists.txt for why).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
