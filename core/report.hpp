// The validation report: the Khronos glTF-Validator's report model (validation.schema.json), which
// every validator step (structure, materials, textures, meshes) appends to and every output format
// (JSON, text, SARIF) reads.
#pragma once
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace gltf_pbr {

// The Khronos numbering: 0 error, 1 warning, 2 information, 3 hint.
enum class Severity : int { Error = 0, Warning = 1, Information = 2, Hint = 3 };

const char* severity_name(Severity severity);  // "error", "warning", "info", "hint"
std::optional<Severity> severity_from_name(std::string_view name);

struct Issue {
  std::string code;     // Khronos code, or ours with a prefix: PBR_*, IMAGE_*, MESH_*
  std::string message;  // one sentence, as the reference words it where the code is its own
  Severity severity = Severity::Error;
  std::string pointer;                  // JSON pointer (RFC 6901) into the document
  std::optional<std::uint64_t> offset;  // byte offset into a GLB, for container issues (no pointer)
  std::uint64_t count = 1;              // identical repeats folded into this one (our addition)
};

// How many distinct messages of one code a report lists by default; the rest are counted.
constexpr std::uint64_t kDefaultMaxListedPerCode = 1000;

struct Report {
  std::string uri;        // as given on the command line, relative paths kept relative
  std::string mime_type;  // "model/gltf+json" or "model/gltf-binary"
  std::vector<Issue> messages;
  bool truncated = false;
  // Counts, resources, extensions. Left null (and omitted from JSON) when the document could not
  // be read far enough to fill it, as the reference does.
  nlohmann::ordered_json info;
  std::vector<std::string> material_names;  // for people: the name of /materials/N, when read
  // Distinct messages listed per code (0: all). Past it, one more message per code stands for the
  // rest with their count, so a file with a million issues keeps a small report and flat memory.
  std::uint64_t max_listed_per_code = kDefaultMaxListedPerCode;

  // Folds an issue identical to one already listed (same code, severity, location and message)
  // into it, and one past max_listed_per_code into its code's unlisted message. Keeps the message
  // and pointer valid UTF-8 (invalid bytes become U+FFFD): a library's error text can quote a
  // file's raw bytes, and every report format is UTF-8 text.
  void add(Issue issue);
  // Whether no more distinct messages of `code` are listed (max_listed_per_code reached).
  bool listing_full(const std::string& code) const {
    const auto found = per_code_.find(code);
    return max_listed_per_code != 0 && found != per_code_.end() && found->second.listed >= max_listed_per_code;
  }
  // Issues found of this severity: a folded message counts every issue it stands for.
  std::uint64_t count(Severity severity) const;

 private:
  // apply_policy rewrites the messages, and with them these indices.
  friend void apply_policy(const struct IssuePolicy& policy, Report& report);
  // Each listed message's index, under the hash of what makes issues identical (report.cpp).
  std::unordered_multimap<std::uint64_t, std::size_t> listed_;
  struct CodeListing {
    std::uint64_t listed = 0;
    std::size_t unlisted = SIZE_MAX;  // index of the message that counts the rest
  };
  std::unordered_map<std::string, CodeListing> per_code_;
};

// What the user config (Khronos YAML config shape: max-issues, ignore, only, override) does to a
// report's messages.
struct IssuePolicy {
  std::uint64_t max_issues = 0;  // 0: unlimited
  std::set<std::string> ignore;
  std::set<std::string> only;  // when non-empty, every other code is dropped
  std::map<std::string, Severity> severity_override;
  std::uint64_t max_listed_per_code = kDefaultMaxListedPerCode;  // ours: max-issues-per-code, 0: all
};

// Drops ignored codes (or all but `only`), applies severity overrides, folds identical repeats
// (same code, severity, message and location) into one message with a count, and truncates at
// max_issues, setting `truncated`. Order is kept: a folded message stays where it first occurred.
void apply_policy(const IssuePolicy& policy, Report& report);

// The report as the Khronos validator writes it (validatorVersion: ours). A folded message carries
// "count" only when it is above 1, so unfolded reports stay schema-identical to the reference.
nlohmann::ordered_json report_to_json(const Report& report);

// The text of report_to_json(report) as every command writes it (indented by 2, U+FFFD for bytes
// that are not UTF-8, a final newline), written a message at a time: a report of a million
// messages never stands as one JSON document in memory.
std::string report_json_text(const Report& report);

// The report that report_to_json wrote (material names aside, which it does not hold): what a
// results cache keeps. Throws nlohmann::json::exception or std::invalid_argument for JSON it did
// not write.
Report report_from_json(const nlohmann::ordered_json& json);

}  // namespace gltf_pbr
