// libFuzzer target: `gltf-pbr convert --preview` on arbitrary bytes: load, the bake of every
// texture (PNG and JPEG decoders, the solver), pruning, the writer, and the preview's renderer on
// the input and its conversion. Bad input must end in an InputError that names the file; anything
// else thrown, a crash, a hang or unbounded memory is a finding. scripts/fuzz.sh runs it seeded
// with small spec-gloss assets packed as GLB (scripts/fuzz_seeds.py).
#include <unistd.h>

#include <cstdint>
#include <fstream>

#include "api/files.hpp"

namespace {
const std::filesystem::path& scratch_folder() {
  static const std::filesystem::path folder = [] {
    auto path = std::filesystem::temp_directory_path() / ("gltf-pbr-fuzz-convert-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  return folder;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool binary = size >= 4 && data[0] == 'g' && data[1] == 'l' && data[2] == 'T' && data[3] == 'F';
  const auto& folder = scratch_folder();
  const auto input = folder / (binary ? "input.glb" : "input.gltf");
  {
    std::ofstream out(input, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  // Each run writes a fresh output and preview: an output left by the last input is not this one's.
  std::filesystem::remove_all(folder / "out");
  gltf_pbr::ConvertFileOptions options;
  options.preview_size = 16;
  options.error_samples = 4096;
  try {
    const gltf_pbr::FileResult result =
        gltf_pbr::convert_or_throw(gltf_pbr::ConvertJob(input, folder / "out" / (binary ? "output.glb" : "output.gltf"),
                                                        folder / "out" / "preview"),
                                   options);
    (void)gltf_pbr::file_json(result).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  } catch (const gltf_pbr::InputError& error) {
    if (error.file.empty()) __builtin_trap();  // a bad input's error names its file
  }
  return 0;
}
