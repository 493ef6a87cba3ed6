// --isolate: each file converted by a child process of this executable, so a crash, a hang or a
// runaway allocation in one file fails that file and the batch goes on (issue 16).
#pragma once
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "api/files.hpp"

namespace gltf_pbr::cli {

struct ChildLimits {
  double seconds = 0;       // wall time a file may take; 0: no limit
  std::uint64_t bytes = 0;  // resident memory a child may use; 0: no limit
};

// Runs `gltf-pbr convert INPUT -o OUTPUT --report SCRATCH/<index>.json <options>` for the job and
// reads the file's entry back from that report. A child that crashes, runs past the time limit or
// above the memory limit (its resident set, sampled every 20 ms, so it holds under the sanitizers
// that reserve terabytes of address space) is killed, and the result is a failure saying which.
// `child_cache` receives the child's report's "cache" block when it has one.
// First thing in main: a process started by convert_in_child dies with the run that started it.
void become_child_of_isolated_run();

FileResult convert_in_child(const ConvertJob& job, const std::vector<std::string>& options, const ChildLimits& limits,
                            const std::filesystem::path& scratch, std::size_t index, nlohmann::json* child_cache);

}  // namespace gltf_pbr::cli
