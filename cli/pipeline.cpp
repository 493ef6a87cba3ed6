#include "cli/pipeline.hpp"

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>

#include "core/error.hpp"

namespace gltf_pbr::cli {

Shard parse_shard(const std::string& text) {
  const auto fail = [&] { return CLI::ValidationError("--shard", "expected I/N with 0 <= I < N, got '" + text + "'"); };
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == text.size()) throw fail();
  const auto number = [&](const std::string& digits) {
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) throw fail();
    return static_cast<std::uint32_t>(std::stoul(digits));
  };
  const Shard shard{number(text.substr(0, slash)), number(text.substr(slash + 1))};
  if (shard.count == 0 || shard.index >= shard.count) throw fail();
  return shard;
}

std::uint32_t shard_of(const InputFile& file, std::uint32_t shard_count) {
  std::uint64_t hash = 14695981039346656037ull;  // FNV-1a, 64-bit offset basis and prime
  for (const char c : file.key.generic_string()) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 1099511628211ull;
  }
  return static_cast<std::uint32_t>(hash % shard_count);
}

std::vector<std::string> read_input_list(const std::string& source) {
  std::ifstream file;
  if (source != "-") {
    std::error_code ec;
    if (std::filesystem::is_directory(source, ec))
      throw CLI::ValidationError("--inputs-from", source + ": a folder, not a list of paths");
    file.open(source);
    if (!file) throw CLI::ValidationError("--inputs-from", source + ": " + std::strerror(errno));
  }
  std::istream& in = source == "-" ? std::cin : file;
  std::vector<std::string> paths;
  std::size_t number = 0;
  for (std::string line; std::getline(in, line);) {
    if (++number == 1 && line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find('\0') != std::string::npos)
      throw CLI::ValidationError("--inputs-from",
                                 source + ": line " + std::to_string(number) + " holds a NUL byte, which no path can");
    if (!line.empty()) paths.push_back(line);
  }
  if (in.bad()) throw CLI::ValidationError("--inputs-from", source + ": read error");
  return paths;
}

ResultsLog::ResultsLog(const std::filesystem::path& path) : path_(path) {
  if (path.empty()) return;
  file_ = std::fopen(path.c_str(), "we");  // e: close-on-exec, not inherited by --isolate's children
  if (!file_) throw OutputError(path.string() + ": " + std::strerror(errno));
}

ResultsLog::~ResultsLog() {
  if (file_) std::fclose(file_);
}

void ResultsLog::write(const std::string& line) {
  if (!file_) return;
  std::lock_guard lock(mutex_);
  if (std::fputs(line.c_str(), file_) < 0 || std::fputc('\n', file_) < 0 || std::fflush(file_) != 0)
    throw OutputError(path_.string() + ": " + std::strerror(errno));
}

GivenInputs all_inputs(std::vector<std::string> named, const PipelineArgs& args) {
  GivenInputs inputs{std::move(named),
                     args.inputs_from.empty() ? std::vector<std::string>{} : read_input_list(args.inputs_from)};
  if (inputs.named.empty() && inputs.listed.empty())
    throw CLI::ValidationError("inputs", "give input files or folders, or --inputs-from");
  return inputs;
}

std::vector<std::size_t> positions_in_shard(const std::vector<InputFile>& files, const PipelineArgs& args) {
  const std::optional<Shard> shard = args.shard.empty() ? std::nullopt : std::optional(parse_shard(args.shard));
  std::vector<std::size_t> positions;
  for (std::size_t i = 0; i < files.size(); ++i)
    if (!shard || shard_of(files[i], shard->count) == shard->index) positions.push_back(i);
  return positions;
}

nlohmann::json sum_of_counts(const std::vector<nlohmann::json>& blocks) {
  nlohmann::json sum = nlohmann::json::object();
  for (const nlohmann::json& block : blocks)
    if (block.is_object())
      for (const auto& [name, value] : block.items()) {
        if (value.is_number_unsigned())
          sum[name] = sum.value(name, std::uint64_t{0}) + value.get<std::uint64_t>();
        else if (!sum.contains(name))
          sum[name] = value;
      }
  return sum;
}

void add_pipeline_options(CLI::App& command, PipelineArgs& args) {
  command.add_option("--inputs-from", args.inputs_from,
                     "also take the inputs listed in FILE, one path per line ('-': standard input)");
  command.add_option("--shard", args.shard,
                     "take only shard I of N (I/N, 0-based): files by a hash of their path under the input root, "
                     "so N runs with I = 0..N-1 split the input without overlap (merge-reports joins their reports)");
  command.add_option("--results", args.results,
                     "write one JSON line per file as it finishes (status, outputs, errors, times), flushed at once");
  add_cache_option(command, args.cache);
}

void add_cache_option(CLI::App& command, std::string& folder) {
  command.add_option("--cache", folder,
                     "keep each file's result in DIR under a hash of its bytes, the files it names, the options, the "
                     "rules and the version, and restore it from there when they are unchanged (several runs may "
                     "share DIR)");
}

}  // namespace gltf_pbr::cli
