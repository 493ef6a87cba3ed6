// `gltf-pbr merge-reports`: the reports of `convert --shard I/N` runs (or the summaries of
// `validate --shard I/N`) joined into the one an unsharded run writes: its files in the unsharded
// order, its totals recounted. Every shard must be there exactly once, from the same tool version
// and options.
#include <algorithm>
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

// Convert's reports are written with sorted keys, validate's summaries in the reference's order:
// read and written in order, each comes out as its unsharded run writes it.
using Json = nlohmann::ordered_json;

bool has_unsigned(const Json& object, const char* key) {
  return object.contains(key) && object[key].is_number_unsigned();
}

// The two kinds of report a sharded run writes: where its per-file entries are, which header
// fields each shard counts for itself (recounted, not compared), and what merging reads of an entry.
struct ReportKind {
  const char* entries;
  std::set<std::string> per_shard;
  void (*check_entry)(const Json& entry, const std::string& file, const std::string& pointer);
};

void refuse_member(const std::string& file, const std::string& pointer, const std::string& expected) {
  throw InputError(file, pointer, "expected " + expected);
}

// A convert report's file entry: the fields the totals read, with the types they read them as, so a
// crafted entry is refused by its pointer instead of reaching the totals as a type error.
void check_conversion_entry(const Json& entry, const std::string& file, const std::string& pointer) {
  if (!entry.is_object()) refuse_member(file, pointer, "an object");
  if (!entry.contains("status") || !entry["status"].is_string()) refuse_member(file, pointer + "/status", "a string");
  if (!entry.contains("timeMs") || !entry["timeMs"].is_object() || !entry["timeMs"].contains("total") ||
      !entry["timeMs"]["total"].is_number())
    refuse_member(file, pointer + "/timeMs/total", "a number");
  if (!entry.contains("materials")) return;
  if (!entry["materials"].is_array()) refuse_member(file, pointer + "/materials", "an array");
  for (std::size_t m = 0; m < entry["materials"].size(); ++m) {
    const Json& material = entry["materials"][m];
    if (!material.is_object() || !material.contains("texels") || !material["texels"].is_number_integer())
      refuse_member(file, pointer + "/materials/" + std::to_string(m) + "/texels", "an integer");
  }
}

constexpr const char* kSeverityCounts[] = {"numErrors", "numWarnings", "numInfos", "numHints"};

// A validate summary's line: its counts and whether it fails.
void check_validation_entry(const Json& entry, const std::string& file, const std::string& pointer) {
  if (!entry.is_object()) refuse_member(file, pointer, "an object");
  for (const char* count : kSeverityCounts)
    if (!has_unsigned(entry, count)) refuse_member(file, pointer + "/" + count, "a count");
  if (!entry.contains("failed") || !entry["failed"].is_boolean()) refuse_member(file, pointer + "/failed", "a boolean");
}

const ReportKind kConversion{"files", {"files", "totals", "shard", "cache"}, check_conversion_entry};
const ReportKind kValidation{
    "reports",
    {"files", "failing", "numErrors", "numWarnings", "numInfos", "numHints", "reports", "shard", "cache"},
    check_validation_entry};

Json read_report(const std::string& file, const ReportKind** kind) {
  const std::optional<Bytes> bytes = read_file(file);
  if (!bytes) throw InputError(file, "", "cannot read the file: " + unreadable_reason(file));
  const auto bounded = [&](int depth, Json::parse_event_t, Json&) {
    if (depth > kMaxDepth) throw InputError(file, "", "nested deeper than any report");
    return true;
  };
  Json report = Json::parse(bytes->begin(), bytes->end(), bounded, /*allow_exceptions=*/false);
  if (report.is_discarded()) throw InputError(file, "", "not valid JSON");
  if (!report.is_object() || !report.contains("tool") || report["tool"] != "gltf-pbr" || !report.contains("files"))
    throw InputError(file, "", "not a report of gltf-pbr convert or a summary of gltf-pbr validate");
  *kind = report.contains("reports") ? &kValidation : &kConversion;
  if (!report.contains("shard") || !report["shard"].is_object() || !has_unsigned(report["shard"], "index") ||
      !has_unsigned(report["shard"], "count") || !has_unsigned(report["shard"], "files"))
    throw InputError(file, "/shard",
                     "not the report of a sharded run (convert --shard I/N --report FILE, or validate --shard I/N "
                     "-f json -o DIR)");
  const std::string entries = (*kind)->entries;
  if (!report[entries].is_array()) throw InputError(file, "/" + entries, "expected an array");
  for (std::size_t f = 0; f < report[entries].size(); ++f)
    (*kind)->check_entry(report[entries][f], file, "/" + entries + "/" + std::to_string(f));
  return report;
}

// The unsharded run's counts, from its entries: the order and names the first shard has them in.
void recount_validation(Json& merged, const Json& first) {
  Json recounted = Json::object();
  for (auto it = first.begin(); it != first.end(); ++it) {
    const std::string& key = it.key();
    if (key == "shard" || key == "cache") continue;
    if (key == "files") {
      recounted[key] = merged["reports"].size();
    } else if (key == "failing") {
      std::size_t failing = 0;
      for (const Json& entry : merged["reports"]) failing += entry["failed"].get<bool>();
      recounted[key] = failing;
    } else if (std::find(std::begin(kSeverityCounts), std::end(kSeverityCounts), key) != std::end(kSeverityCounts)) {
      std::uint64_t sum = 0;
      for (const Json& entry : merged["reports"]) sum += entry[key].get<std::uint64_t>();
      recounted[key] = sum;
    } else {
      recounted[key] = merged[key];
    }
  }
  merged = std::move(recounted);
}

Json merge(const std::vector<std::string>& files) {
  std::vector<Json> reports;
  const ReportKind* kind = nullptr;
  for (const std::string& file : files) {
    const ReportKind* this_kind = nullptr;
    reports.push_back(read_report(file, &this_kind));
    if (kind && this_kind != kind)
      throw InputError(file, "", "a different kind of report from " + files.front() + ": not shards of one run");
    kind = this_kind;
  }
  const std::string entries_key = kind->entries;
  const Json& first = reports.front();
  const std::size_t shard_count = first["shard"]["count"], total = first["shard"]["files"];
  // The same run split N ways: every header field but those each shard counts for itself must agree.
  Json header = first;
  for (const std::string& key : kind->per_shard) header.erase(key);
  std::vector<nlohmann::json> caches;  // each shard's count of what it restored: added up
  std::set<std::size_t> shards_seen;
  std::size_t entries = 0;
  for (std::size_t r = 0; r < reports.size(); ++r) {
    Json& report = reports[r];
    const std::string& file = files[r];
    for (auto it = header.begin(); it != header.end(); ++it)
      if (report[it.key()] != it.value())
        throw InputError(file, "/" + escape_pointer_token(it.key()),
                         "differs from " + files.front() + ": not shards of one run");
    for (auto it = report.begin(); it != report.end(); ++it)
      if (!header.contains(it.key()) && !kind->per_shard.contains(it.key()))
        throw InputError(file, "/" + escape_pointer_token(it.key()),
                         "not in " + files.front() + ": not shards of one run");
    if (report["shard"]["count"] != shard_count || report["shard"]["files"] != total)
      throw InputError(file, "/shard", "a different split from " + files.front());
    const std::size_t index = report["shard"]["index"];
    if (index >= shard_count) throw InputError(file, "/shard/index", "beyond the shard count");
    if (!shards_seen.insert(index).second)
      throw InputError(file, "/shard/index", "shard " + std::to_string(index) + " given twice");
    entries += report[entries_key].size();
    if (report.contains("cache")) {
      const Json& cache = report["cache"];
      if (!cache.is_object()) throw InputError(file, "/cache", "expected an object of counts");
      for (auto it = cache.begin(); it != cache.end(); ++it)
        if (it.key() != "folder" && !it.value().is_number_unsigned())
          throw InputError(file, "/cache/" + escape_pointer_token(it.key()), "expected a count");
      caches.push_back(nlohmann::json::parse(cache.dump()));
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
  std::vector<Json> by_position(total);
  for (std::size_t r = 0; r < reports.size(); ++r) {
    for (std::size_t f = 0; f < reports[r][entries_key].size(); ++f) {
      Json& entry = reports[r][entries_key][f];
      const std::string pointer = "/" + entries_key + "/" + std::to_string(f) + "/position";
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
  Json merged = std::move(header);
  merged[entries_key] = Json::array();
  for (Json& entry : by_position) merged[entries_key].push_back(std::move(entry));
  if (kind == &kConversion) {
    const nlohmann::json totals = conversion_totals(nlohmann::json::parse(merged["files"].dump()));
    merged["totals"] = Json::parse(totals.dump());
  } else {
    recount_validation(merged, first);
  }
  if (!caches.empty()) merged["cache"] = Json::parse(sum_of_counts(caches).dump());
  // Shards run with and without --cache: the counts are those of the shards that had one, and say so.
  if (!caches.empty() && caches.size() < shard_count)
    merged["cache"]["shards"] = Json{{"counted", caches.size()}, {"of", shard_count}};
  if (kind == &kConversion)
    merged = Json::parse(nlohmann::json::parse(merged.dump()).dump());  // keys sorted, as convert writes them
  return merged;
}

int run(const MergeArgs& args) {
  write_output(args.output, json_text(merge(args.reports)));
  return kAllDone;
}

constexpr const char* kMergeHelp =
    R"(Join the reports of `convert --shard I/N --report FILE` runs (or the summaries of `validate --shard I/N
-f json -o DIR`) into the report of one unsharded run: files in the unsharded order, totals
recounted. Refuses a missing, repeated or foreign shard.
Exit codes: 0 merged, 2 the reports do not make one run, 3 the output cannot be written.)";

void declare_options(CLI::App& cmd, MergeArgs& args) {
  cmd.add_option("reports", args.reports, "the shards' --report files, in any order")->required();
  cmd.add_option("-o,--output", args.output, "write the merged report here (default: standard output)");
}

}  // namespace

std::function<int()> add_merge_command(CLI::App& app) {
  return add_subcommand<MergeArgs>(app, "merge-reports", kMergeHelp, declare_options, run);
}

}  // namespace gltf_pbr::cli
