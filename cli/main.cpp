// gltf-pbr: legacy glTF materials to albedo + metalness, with error reports.
#include <cstdio>
#include <sstream>
#include <string_view>

#include "cli/commands.hpp"
#include "cli/isolate.hpp"
#include "core/files.hpp"
#include "core/text.hpp"
#include "core/version.hpp"

int main(int argc, char** argv) {
  gltf_pbr::cli::become_child_of_isolated_run();
  gltf_pbr::install_signal_cleanup();  // before any worker thread: they inherit its signal mask
  CLI::App app{
      "gltf-pbr: turns legacy KHR_materials_pbrSpecularGlossiness glTF materials into physically based\n"
      "albedo + metalness (core pbrMetallicRoughness) and reports the error each material took on;\n"
      "validates glTF structure, material plausibility, textures and meshes; previews before and after."};
  app.set_version_flag("--version", gltf_pbr::tool_name_and_version());
  app.require_subcommand(1);
  const auto run_convert = gltf_pbr::cli::add_convert_command(app);
  const auto run_compare = gltf_pbr::cli::add_compare_command(app);
  const auto run_validate = gltf_pbr::cli::add_validate_command(app);
  const auto run_preview = gltf_pbr::cli::add_preview_command(app);
  const auto run_merge = gltf_pbr::cli::add_merge_command(app);
  const auto run_gallery = gltf_pbr::cli::add_gallery_command(app);
  // CLI11 would call an unknown first word "A subcommand is required"; name it instead.
  if (argc > 1 && argv[1][0] != '-') {
    const std::string_view word = argv[1];
    std::string commands;
    bool known = false;
    for (const CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) {
      commands += (commands.empty() ? "" : ", ") + command->get_name();
      known = known || command->get_name() == word;
    }
    if (!known) {
      std::fprintf(stderr, "gltf-pbr: unknown command '%s'; the commands are %s (gltf-pbr --help)\n",
                   gltf_pbr::printable(word).c_str(), commands.c_str());
      return gltf_pbr::cli::kBadUsage;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 quotes the arguments it refuses, and arguments come from file names: escape each line.
    std::ostringstream out, err;
    const int code = app.exit(e, out, err);
    auto print = [](const std::string& text, std::FILE* stream) {
      std::istringstream lines(text);
      for (std::string line; std::getline(lines, line);)
        std::fprintf(stream, "%s\n", gltf_pbr::printable(line).c_str());
    };
    print(out.str(), stdout);
    print(err.str(), stderr);
    return code == 0 ? 0 : gltf_pbr::cli::kBadUsage;
  }
  // Each runner returns -1 unless its subcommand was the one given.
  for (const auto& run : {run_convert, run_compare, run_validate, run_preview, run_merge, run_gallery})
    if (const int code = run(); code >= 0) return code;
  return gltf_pbr::cli::kBadUsage;
}
