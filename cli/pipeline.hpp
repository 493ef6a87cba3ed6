// What batch runs in build pipelines share: inputs from a list, deterministic shards of the input,
// and results written line by line as files finish (issue 16).
#pragma once
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/inputs.hpp"

namespace CLI {
class App;
}

namespace gltf_pbr::cli {

// --shard I/N: this run takes shard I (0-based) of N.
struct Shard {
  std::uint32_t index = 0, count = 1;
};

// "I/N" in decimal digits with 0 <= I < N; throws CLI::ValidationError otherwise.
Shard parse_shard(const std::string& text);

// The file's shard: FNV-1a (64-bit) of its path relative to the input root, in generic form, mod
// N. It depends only on that path, so every machine puts a file in the same shard, the shards are
// disjoint and together cover the input, and adding files never moves the others.
std::uint32_t shard_of(const InputFile& file, std::uint32_t shard_count);

// --inputs-from FILE, or "-" for stdin: one path per line, as if given on the command line; empty
// lines are skipped, a Windows line end's CR and a leading UTF-8 byte-order mark are dropped.
// Throws CLI::ValidationError naming the list (and the line) when it cannot be read or a line
// holds a NUL byte, which no path can.
std::vector<std::string> read_input_list(const std::string& source);

// --results FILE.jsonl: one JSON object per line, each written and flushed as its file finishes,
// so a driver or `tail -f` can follow a long run. A log, not an output: it grows as the run goes
// and is complete when the run ends. Throws OutputError when it cannot be written.
class ResultsLog {
 public:
  explicit ResultsLog(const std::filesystem::path& path);  // empty path: no log
  ~ResultsLog();
  ResultsLog(const ResultsLog&) = delete;
  ResultsLog& operator=(const ResultsLog&) = delete;
  void write(const std::string& line);  // one line, without its newline; any thread

 private:
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::mutex mutex_;
};

// Several runs' "cache" blocks (shards, --isolate children) as one run's: counts added up, the
// rest (the folder) as the first block has it. Blocks that are not objects are left out.
nlohmann::json sum_of_counts(const std::vector<nlohmann::json>& blocks);

// --inputs-from, --shard, --results and --cache, for a batch subcommand.
struct PipelineArgs {
  std::string inputs_from, shard, results, cache;
};

// The inputs named on the command line and those --inputs-from lists; throws
// CLI::ValidationError when there are none.
GivenInputs all_inputs(std::vector<std::string> named, const PipelineArgs& args);

// The positions in the whole run of the files this run takes: all of them, or --shard's part.
// The whole run is found first, so every shard sees the same run and a file keeps its place in it.
std::vector<std::size_t> positions_in_shard(const std::vector<InputFile>& files, const PipelineArgs& args);
void add_pipeline_options(CLI::App& command, PipelineArgs& args);
// --cache alone, for a command that takes no other pipeline option yet.
void add_cache_option(CLI::App& command, std::string& folder);

}  // namespace gltf_pbr::cli
