// The one version number of the tool: the CMake project's (project(... VERSION ...)), compiled
// into core. --version, every report and the installed package all take it from here.
#pragma once

namespace gltf_pbr {

const char* tool_version();           // "0.1.0"
const char* tool_name_and_version();  // "gltf-pbr 0.1.0"

}  // namespace gltf_pbr
