#include "cli/inputs.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>

namespace gltf_pbr::cli {
namespace fs = std::filesystem;

bool is_gltf_file(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".gltf" || ext == ".glb";
}

std::vector<InputFile> find_gltf_files(const std::vector<std::string>& inputs) {
  std::vector<InputFile> files;
  for (const fs::path input : inputs) {
    std::error_code ec;
    if (fs::is_directory(input, ec)) {
      std::vector<fs::path> found;
      for (const auto& entry : fs::recursive_directory_iterator(input, ec))
        if (entry.is_regular_file() && is_gltf_file(entry.path())) found.push_back(entry.path());
      std::sort(found.begin(), found.end());
      for (const auto& file : found)
        files.push_back({file, input.filename().empty() ? file.lexically_relative(input)
                                                        : input.filename() / file.lexically_relative(input)});
    } else if (fs::is_regular_file(input, ec)) {
      files.push_back({input, input.filename()});
    } else {
      throw CLI::ValidationError("input", input.string() + ": no such file or directory");
    }
  }
  if (files.empty()) throw CLI::ValidationError("input", "no .gltf or .glb files found");
  return files;
}

Progress::Progress(std::size_t total, bool enabled, std::string verb)
    : total_(total), on_terminal_(enabled && ::isatty(STDERR_FILENO)), verb_(std::move(verb)) {}

void Progress::done(const std::string& line) {
  std::lock_guard lock(mutex_);
  ++count_;
  if (on_terminal_) std::fprintf(stderr, "\r\033[K");
  std::fputs(line.c_str(), stderr);
  if (on_terminal_ && count_ < total_) std::fprintf(stderr, "[%zu/%zu] %s...", count_, total_, verb_.c_str());
  std::fflush(stderr);
}

}  // namespace gltf_pbr::cli
