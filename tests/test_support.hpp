// Shared test helpers: paths to ../shared, scratch folders, and small assets built in code.
#pragma once
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/asset.hpp"

namespace gltf_pbr::test {

// Whether this test program is built with AddressSanitizer: GCC defines __SANITIZE_ADDRESS__,
// clang answers __has_feature(address_sanitizer).
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kBuiltWithAddressSanitizer = true;
#elif defined(__has_feature)
inline constexpr bool kBuiltWithAddressSanitizer = __has_feature(address_sanitizer);
#else
inline constexpr bool kBuiltWithAddressSanitizer = false;
#endif

inline fs::path shared_dir() { return GLTF_PBR_SHARED_DIR; }
inline fs::path assets_dir() { return shared_dir() / "assets"; }

// A fresh folder under the system temp dir, removed when the test ends.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("gltf-pbr-test-" + std::string(info->test_suite_name()) + "-" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

// Every file below a folder, for "nothing was written" checks.
inline std::vector<fs::path> files_under(const fs::path& folder) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) files.push_back(entry.path());
  return files;
}

inline std::string read_text(const fs::path& path) {
  auto bytes = read_file(path);
  return bytes ? std::string(bytes->begin(), bytes->end()) : std::string();
}

inline void write_text(const fs::path& path, const std::string& text) {
  AtomicWriteSet files;
  files.stage(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  files.commit();
}

inline void write_bytes(const fs::path& path, std::span<const std::uint8_t> bytes) {
  AtomicWriteSet files;
  files.stage(path, bytes);
  files.commit();
}

inline constexpr const char* kSpecGloss = "KHR_materials_pbrSpecularGlossiness";

// A JSON array of numbers, as a factor is written.
inline tinygltf::Value numbers(std::initializer_list<double> values) {
  tinygltf::Value::Array array;
  for (double v : values) array.emplace_back(v);
  return tinygltf::Value(std::move(array));
}

// A shared asset's folder: assets/<model>/<variant>.
inline fs::path model_folder(const std::string& model, const std::string& variant = "specgloss") {
  return assets_dir() / model / variant;
}

// Copies the files of a shared asset's folder into `destination`, leaving out `except`: the test's
// own working copy, writable like a user's (../shared is read-only). Returns the copy of
// <model>.gltf, the file of a spec-gloss folder.
inline fs::path copy_model(const std::string& model, const fs::path& destination, const std::string& except = "",
                           const std::string& variant = "specgloss") {
  fs::create_directories(destination);
  for (const auto& entry : fs::directory_iterator(model_folder(model, variant)))
    if (entry.path().filename() != except) {
      fs::copy_file(entry.path(), destination / entry.path().filename());
      fs::permissions(destination / entry.path().filename(), fs::perms::owner_write, fs::perm_options::add);
    }
  return destination / (model + ".gltf");
}

inline std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `gltf-pbr <arguments>` with stdout and stderr captured in files beside (not in) the folders
// the tests inspect.
inline CliResult run_cli(const std::string& arguments, const ScratchDir& scratch) {
  const fs::path out_file = scratch / "cli-stdout.txt", err_file = scratch / "cli-stderr.txt";
  const std::string command =
      quoted(GLTF_PBR_CLI) + " " + arguments + " >" + quoted(out_file) + " 2>" + quoted(err_file);
  const int status = std::system(command.c_str());
  CliResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = read_text(out_file);
  result.err = read_text(err_file);
  fs::remove(out_file);
  fs::remove(err_file);
  return result;
}

}  // namespace gltf_pbr::test
