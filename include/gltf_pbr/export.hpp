// What the shared library libgltf_pbr.so exports: everything else in it is hidden (CMakeLists.txt
// compiles the whole project with hidden visibility), so its symbols never clash with a host's.
#pragma once

#define GLTF_PBR_API __attribute__((visibility("default")))
