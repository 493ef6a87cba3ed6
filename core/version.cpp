#include "core/version.hpp"

namespace gltf_pbr {

const char* tool_version() { return GLTF_PBR_VERSION; }
const char* tool_name_and_version() { return "gltf-pbr " GLTF_PBR_VERSION; }

}  // namespace gltf_pbr
