// The gltf-pbr subcommands. Exit codes (gltfpack style, one per failure class):
#pragma once
#include <CLI/CLI.hpp>

namespace gltf_pbr::cli {

enum ExitCode { kAllDone = 0, kSomeFilesFailed = 1, kBadUsage = 2 };

// Each registers a subcommand; the returned callback runs it after parsing, or returns -1 when
// another subcommand was given.
std::function<int()> add_convert_command(CLI::App& app);
std::function<int()> add_compare_command(CLI::App& app);
std::function<int()> add_validate_command(CLI::App& app);
std::function<int()> add_preview_command(CLI::App& app);

}  // namespace gltf_pbr::cli
