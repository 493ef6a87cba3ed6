// The gltf-pbr subcommands. Exit codes (gltfpack style, one per failure class):
#pragma once
#include <CLI/CLI.hpp>

namespace gltf_pbr::cli {

enum ExitCode { kAllDone = 0, kSomeFilesFailed = 1, kBadUsage = 2 };

// Registers `convert` on the app; the returned callback runs it after parsing.
std::function<int()> add_convert_command(CLI::App& app);

}  // namespace gltf_pbr::cli
