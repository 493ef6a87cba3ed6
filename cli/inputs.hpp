// What every batch subcommand shares: expanding inputs into glTF files, and progress on a terminal.
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "gltf_pbr/gltf_pbr.hpp"

namespace CLI {
class App;
}

namespace gltf_pbr::cli {

struct InputFile {
  std::filesystem::path file;      // as found (relative inputs stay relative)
  std::filesystem::path relative;  // where it goes under an output folder: the input folder's name / path inside it
  std::filesystem::path key;       // what --shard hashes: the path under the input root, whatever the root's name
};

// The inputs named on the command line and those --inputs-from lists.
struct GivenInputs {
  std::vector<std::string> named, listed;
};

// "1 file", "3 files": a count with its noun in the right number.
std::string counted(std::size_t count, const std::string& noun);

// --max-image-pixels N, for every command that decodes images (core/image.hpp's limit).
void add_image_limit_option(CLI::App& command);

// The conversion's settings, as convert and preview take them (--target, --solver, --error-model,
// --metalness-tolerance), the names spelled as api/names.cpp spells them; CLI11 checks them.
struct ConversionArgs {
  std::string target = "metalness", solver = "balanced", error_model = "normal-incidence";
  double metalness_tolerance = ConvertFileOptions().metalness_tolerance;
};
void add_conversion_options(CLI::App& command, ConversionArgs& args);

// What the batch commands share: -j (files at once), --max-image-pixels and --allow-outside-uris.
// `verb` says what happens to a file ("converted", "validated").
void add_batch_options(CLI::App& command, const std::string& verb, unsigned& jobs, bool& allow_outside);

struct FoundInputs {
  std::vector<InputFile> files;
  std::size_t skipped_under_output = 0;  // found inside the output folder: earlier outputs, not inputs
};

// Files are taken as given; directories are searched recursively for .gltf and .glb, in sorted
// order, leaving out what lies under `output_folder` (when given) so a rerun never converts its own
// outputs. A named file goes to its name under an output folder; a listed one to its path as listed
// when that is relative and stays below where it is read from (a list of changed files, `git diff
// --name-only`, updates what a run over their folder wrote), else to its name. Throws
// CLI::ValidationError for a missing named input or when nothing is found; a missing listed file
// is kept, for the run to fail on it alone (a list of changes names deleted files). A file named
// twice (listed twice, or beside a folder holding it) is one input, where it was first found.
FoundInputs find_gltf_files(const GivenInputs& inputs, const std::filesystem::path& output_folder = {});

// One run never writes an output twice: throws CLI::ValidationError naming both inputs when two
// would go to the same output (the same file given twice, or a/Box.gltf and b/Box.gltf as files
// under one -o folder). outputs[i] belongs to files[i]; `remedy` ends the message.
void refuse_shared_outputs(const std::vector<InputFile>& files, const std::vector<std::filesystem::path>& outputs,
                           const std::string& remedy = "give their folders instead, or run them separately");

// What a run reads besides its inputs' own files, for refuse_writing_over_inputs.
struct RunReads {
  bool allow_outside_uris = false;  // the inputs may name files outside their folders
  std::string inputs_from;          // --inputs-from's list ("-": standard input)
  std::string config;               // validate's --config file
};
// A file a run will write, and the option that named it (for the message). With `names`, `path`
// is a folder and the run may write there any file whose name `names` accepts (names known only
// as they are written, as validate's heat maps).
struct PlannedOutput {
  std::filesystem::path path;
  std::string option;
  std::function<bool(const std::string& name)> names = {};
};
// A run never writes over what it reads: throws CLI::ValidationError when a planned output (a
// report, a results log, a preview's images) is one of the inputs, a file an input names (a
// buffer, an image), the input list or the config file. Only an existing file can be one; only inputs whose folder
// holds one (any input, where URIs may leave their folder) are read for the files they name.
void refuse_writing_over_inputs(const std::vector<InputFile>& files, std::span<const PlannedOutput> outputs,
                                const RunReads& reads);

bool is_gltf_file(const std::filesystem::path& path);

// "[done/total] <verb>..." kept on the last line of a terminal (also when quiet: it is erased at the
// end), with the lines of finished files printed above it.
class Progress {
 public:
  Progress(std::size_t total, std::string verb);
  ~Progress();
  void done(const std::string& line);  // an empty line: counted, nothing printed

 private:
  void show_count();
  std::size_t total_, count_ = 0;
  bool on_terminal_;
  std::string verb_;
  std::mutex mutex_;
};

}  // namespace gltf_pbr::cli
