// `gltf-pbr merge-reports`: the reports of `convert --shard I/N` runs joined into the report one
// unsharded run writes: its files in the unsharded order, its totals recounted. Every shard must
// be there exactly once, from the same tool version and options.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>

#include "api/files.hpp"
#include "cli/commands.hpp"
#include "cli/pipeline.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "core/json_pointer.hpp"

namespace gltf_pbr::cli {
namespace {

using nlohmann::json;

struct MergeArgs {
  std::vector<std::string> reports;
  std::string output;
};

constexpr int kMaxDepth = 64;  // a report nests 6 levels; deeper is not one, and recursion must stay bounded

bool has_unsigned(const json& object, const char* key) {
  return object.contains(key) && object[key].is_number_unsigned();
}

// The fields merging reads of a file entry, with the types it reads them as: a crafted entry is
// refused by its pointer instead of reaching the totals as a type error.
void check_entry(const json& entry, const std::string& file, const std::string& pointer) {
  const auto refuse = [&](const std::string& member, const std::string& expected) {
    throw InputError(file, pointer + member, "expected " + expected);
  };
  if (!entry.is_object()) refuse("", "an object");
  if (!entry.contains("status") || !entry["status"].is_string()) refuse("/status", "a string");
  if (!entry.contains("timeMs") || !entry["timeMs"].is_object() || !entry["timeMs"].contains("total") ||
      !entry["timeMs"]["total"].is_number())
    refuse("/timeMs/total", "a number");
  if (!entry.contains("materials")) return;
  if (!entry["materials"].is_array()) refuse("/materials", "an array");
  for (std::size_t m = 0; m < entry["materials"].size(); ++m) {
    const json& material = entry["materials"][m];
    if (!material.is_object() || !material.contains("texels") || !material["texels"].is_number_integer())
      refuse("/materials/" + std::to_string(m) + "/texels", "an integer");
  }
}

json read_report(const std::string& file) {
  const std::optional<Bytes> bytes = read_file(file);
  if (!bytes) throw InputError(file, "", "cannot read the file");
  const auto bounded = [&](int depth, json::parse_event_t, json&) {
    if (depth > kMaxDepth) throw InputError(file, "", "nested deeper than any report");
    return true;
  };
  json report = json::parse(bytes->begin(), bytes->end(), bounded, /*allow_exceptions=*/false);
  if (report.is_discarded()) throw InputError(file, "", "not valid JSON");
  if (!report.is_object() || !report.contains("tool") || report["tool"] != "gltf-pbr" || !report.contains("files"))
    throw InputError(file, "", "not a report of gltf-pbr convert");
  if (!report.contains("shard") || !report["shard"].is_object() || !has_unsigned(report["shard"], "index") ||
      !has_unsigned(report["shard"], "count") || !has_unsigned(report["shard"], "files"))
    throw InputError(file, "/shard", "not the report of a sharded run (convert --shard I/N --report FILE)");
  if (!report["files"].is_array()) throw InputError(file, "/files", "expected an array");
  for (std::size_t f = 0; f < report["files"].size(); ++f)
    check_entry(report["files"][f], file, "/files/" + std::to_string(f));
  return report;
}

json merge(const std::vector<std::string>& files) {
  std::vector<json> reports;
  for (const std::string& file : files) reports.push_back(read_report(file));
  const json& first = reports.front();
  const std::size_t shard_count = first["shard"]["count"], total = first["shard"]["files"];
  // The same run split N ways: every header field but the shard index must agree.
  json header = first;
  // "cache" is each shard's own count of what it restored: added up, not compared.
  header.erase("files"), header.erase("totals"), header.erase("shard"), header.erase("cache");
  std::vector<json> caches;
  std::set<std::size_t> shards_seen;
  std::size_t entries = 0;
  for (std::size_t r = 0; r < reports.size(); ++r) {
    json& report = reports[r];
    const std::string& file = files[r];
    for (auto it = header.begin(); it != header.end(); ++it)
      if (report[it.key()] != it.value())
        throw InputError(file, "/" + escape_pointer_token(it.key()),
                         "differs from " + files.front() + ": not shards of one run");
    for (auto it = report.begin(); it != report.end(); ++it)
      if (!header.contains(it.key()) && it.key() != "files" && it.key() != "totals" && it.key() != "shard" &&
          it.key() != "cache")
        throw InputError(file, "/" + escape_pointer_token(it.key()),
                         "not in " + files.front() + ": not shards of one run");
    if (report["shard"]["count"] != shard_count || report["shard"]["files"] != total)
      throw InputError(file, "/shard", "a different split from " + files.front());
    const std::size_t index = report["shard"]["index"];
    if (index >= shard_count) throw InputError(file, "/shard/index", "beyond the shard count");
    if (!shards_seen.insert(index).second)
      throw InputError(file, "/shard/index", "shard " + std::to_string(index) + " given twice");
    entries += report["files"].size();
    if (report.contains("cache")) {
      const json& cache = report["cache"];
      if (!cache.is_object()) throw InputError(file, "/cache", "expected an object of counts");
      for (auto it = cache.begin(); it != cache.end(); ++it)
        if (it.key() != "folder" && !it.value().is_number_unsigned())
          throw InputError(file, "/cache/" + escape_pointer_token(it.key()), "expected a count");
      caches.push_back(cache);
    }
  }
  // Counts come from the files: they are checked against what was given before anything is
  // allocated by them.
  if (shards_seen.size() != shard_count) {
    std::size_t missing = 0;
    while (shards_seen.contains(missing)) ++missing;
    throw InputError(files.front(), "/shard",
                     "shard " + std::to_string(missing) + " of " + std::to_string(shard_count) + " is missing" +
                         (shard_count - shards_seen.size() > 1
                              ? " (and " + std::to_string(shard_count - shards_seen.size() - 1) + " more)"
                              : ""));
  }
  if (entries != total)
    throw InputError(files.front(), "/shard/files",
                     "a run of " + std::to_string(total) + " files, but the shards report " + std::to_string(entries));
  std::vector<json> by_position(total);
  for (std::size_t r = 0; r < reports.size(); ++r) {
    for (std::size_t f = 0; f < reports[r]["files"].size(); ++f) {
      json& entry = reports[r]["files"][f];
      const std::string pointer = "/files/" + std::to_string(f) + "/position";
      if (!has_unsigned(entry, "position") || entry["position"] >= total)
        throw InputError(files[r], pointer, "expected a position below " + std::to_string(total));
      const std::size_t position = entry["position"];
      if (!by_position[position].is_null())
        throw InputError(files[r], pointer, "position " + std::to_string(position) + " is in two shards");
      entry.erase("position");
      by_position[position] = std::move(entry);
    }
  }
  // Every position is now filled: as many entries as positions, none twice.
  json merged = std::move(header);
  merged["files"] = json::array();
  for (json& entry : by_position) merged["files"].push_back(std::move(entry));
  merged["totals"] = conversion_totals(merged["files"]);
  if (!caches.empty()) merged["cache"] = sum_of_counts(caches);
  return merged;
}

int run(const MergeArgs& args) {
  write_output(args.output, json_text(merge(args.reports)));
  return kAllDone;
}

}  // namespace

std::function<int()> add_merge_command(CLI::App& app) {
  auto args = std::make_shared<MergeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "merge-reports",
      "Join the reports of `convert --shard I/N --report FILE` runs into the report of one unsharded run:\n"
      "files in the unsharded order, totals recounted. Refuses a missing, repeated or foreign shard.\n"
      "Exit codes: 0 merged, 2 the reports do not make one run, 3 the output cannot be written.");
  cmd->add_option("reports", args->reports, "the shards' --report files, in any order")->required();
  cmd->add_option("-o,--output", args->output, "write the merged report here (default: standard output)");
  return [cmd, args]() -> int {
    if (!cmd->parsed()) return -1;
    return run_command("merge-reports", [&] { return run(*args); });
  };
}

}  // namespace gltf_pbr::cli
