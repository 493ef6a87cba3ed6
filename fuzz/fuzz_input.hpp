// What the libFuzzer targets share: each input goes through a file, because the tool reads paths
// (and resolves URIs beside them), in a private folder per process so parallel jobs keep apart.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace gltf_pbr::fuzz {

// The folder of this process's inputs (and outputs), made on first use.
inline const std::filesystem::path& scratch_folder(const char* target) {
  static const std::filesystem::path folder = [&] {
    auto path = std::filesystem::temp_directory_path() /
                ("gltf-pbr-fuzz-" + std::string(target) + "-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  return folder;
}

// The bytes written as the scratch folder's input.glb (they start as a GLB does) or input.gltf.
inline std::filesystem::path write_input(const char* target, const std::uint8_t* data, std::size_t size) {
  const bool binary = size >= 4 && data[0] == 'g' && data[1] == 'l' && data[2] == 'T' && data[3] == 'F';
  const auto file = scratch_folder(target) / (binary ? "input.glb" : "input.gltf");
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

}  // namespace gltf_pbr::fuzz
