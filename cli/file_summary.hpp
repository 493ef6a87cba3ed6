// A converted file for people: one line, and one per material worth a look, on stderr.
#pragma once
#include <string>

#include "api/files.hpp"

namespace gltf_pbr::cli {

std::string file_summary(const FileResult& result, bool verbose);

}  // namespace gltf_pbr::cli
