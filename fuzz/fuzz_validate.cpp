// libFuzzer target: the whole `gltf-pbr validate` path (structure on the raw bytes, then load +
// materials + textures + meshes) on arbitrary bytes. It must never crash, hang or grow without
// bound; scripts/fuzz.sh runs it for a bounded time, seeded from the Khronos validator suite.
#include "fuzz/fuzz_input.hpp"
#include "validators/validate.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path file = gltf_pbr::fuzz::write_input("validate", data, size);
  gltf_pbr::ValidateOptions options;
  const gltf_pbr::Report report =
      gltf_pbr::validate_file(file, file.filename().string(), gltf_pbr::builtin_rules(), {}, options);
  (void)gltf_pbr::report_to_json(report).dump();
  return 0;
}
