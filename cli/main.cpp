// gltf-pbr: legacy glTF materials to albedo + metalness, with error reports.
#include <cstdio>

#include "cli/commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "gltf-pbr: turns legacy KHR_materials_pbrSpecularGlossiness glTF materials into physically based\n"
      "albedo + metalness (core pbrMetallicRoughness) and reports the error each material took on;\n"
      "validates glTF structure, material plausibility, textures and meshes; previews before and after."};
  app.set_version_flag("--version", "gltf-pbr 0.1.0");
  app.require_subcommand(1);
  const auto run_convert = gltf_pbr::cli::add_convert_command(app);
  const auto run_compare = gltf_pbr::cli::add_compare_command(app);
  const auto run_validate = gltf_pbr::cli::add_validate_command(app);
  const auto run_preview = gltf_pbr::cli::add_preview_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : gltf_pbr::cli::kBadUsage;
  }
  // Each runner returns -1 unless its subcommand was the one given.
  for (const auto& run : {run_convert, run_compare, run_validate, run_preview})
    if (const int code = run(); code >= 0) return code;
  return gltf_pbr::cli::kBadUsage;
}
