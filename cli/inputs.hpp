// What every batch subcommand shares: expanding inputs into glTF files, and progress on a terminal.
#pragma once
#include <cstddef>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

namespace gltf_pbr::cli {

struct InputFile {
  std::filesystem::path file;      // as found (relative inputs stay relative)
  std::filesystem::path relative;  // where it goes under an output folder: the input folder's name / path inside it
};

// Files are taken as given; directories are searched recursively for .gltf and .glb, in sorted
// order. Throws CLI::ValidationError for a missing input or when nothing is found.
std::vector<InputFile> find_gltf_files(const std::vector<std::string>& inputs);

bool is_gltf_file(const std::filesystem::path& path);

// One line per finished file, and "[done/total] <verb>..." kept on the last line of a terminal.
class Progress {
 public:
  Progress(std::size_t total, bool enabled, std::string verb);
  void done(const std::string& line);

 private:
  std::size_t total_, count_ = 0;
  bool on_terminal_;
  std::string verb_;
  std::mutex mutex_;
};

}  // namespace gltf_pbr::cli
