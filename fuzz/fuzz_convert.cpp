// libFuzzer target: `gltf-pbr convert --preview` on arbitrary bytes: load, the bake of every
// texture (PNG and JPEG decoders, the solver), pruning, the writer, and the preview's renderer on
// the input and its conversion. Bad input must end in an InputError that names the file; anything
// else thrown, a crash, a hang or unbounded memory is a finding. scripts/fuzz.sh runs it seeded
// with small spec-gloss assets packed as single files (scripts/fuzz_seeds.py).
#include "api/files.hpp"
#include "fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path input = gltf_pbr::fuzz::write_input("convert", data, size);
  const bool binary = input.extension() == ".glb";
  const std::filesystem::path folder = input.parent_path();
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
