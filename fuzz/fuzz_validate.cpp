// libFuzzer target: the whole `gltf-pbr validate` path (structure on the raw bytes, then load +
// materials + textures + meshes) on arbitrary bytes. It must never crash, hang or grow without
// bound; scripts/fuzz.sh runs it for a bounded time, seeded from the Khronos validator suite.
#include <unistd.h>

#include <cstdint>
#include <fstream>

#include "validators/validate.hpp"

namespace {
// Inputs go through a file because validate_file reads paths (and resolves URIs beside them).
// A private folder per process keeps parallel fuzzing jobs apart.
const std::filesystem::path& scratch_folder() {
  static const std::filesystem::path folder = [] {
    auto path = std::filesystem::temp_directory_path() / ("gltf-pbr-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  return folder;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool binary = size >= 4 && data[0] == 'g' && data[1] == 'l' && data[2] == 'T' && data[3] == 'F';
  const auto file = scratch_folder() / (binary ? "input.glb" : "input.gltf");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  gltf_pbr::ValidateOptions options;
  const gltf_pbr::Report report =
      gltf_pbr::validate_file(file, file.filename().string(), gltf_pbr::builtin_rules(), {}, options);
  (void)gltf_pbr::report_to_json(report).dump();
  return 0;
}
