#include "core/report.hpp"

#include <algorithm>
#include <stdexcept>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include "core/enum_names.hpp"
#include "core/text.hpp"
#include "core/version.hpp"

namespace gltf_pbr {

constexpr NameTable<Severity, 4> kSeverityNames{{{Severity::Error, "error"},
                                                 {Severity::Warning, "warning"},
                                                 {Severity::Information, "info"},
                                                 {Severity::Hint, "hint"}}};

const char* severity_name(Severity severity) { return name_of(kSeverityNames, severity); }
std::optional<Severity> severity_from_name(std::string_view name) { return from_name(kSeverityNames, name); }

std::uint64_t Report::count(Severity severity) const {
  std::uint64_t found = 0;
  for (const Issue& issue : messages)
    if (issue.severity == severity) found += issue.count;
  return found;
}

namespace {
// Identical issues (same code, severity, location and message) fold into one message. A hash of
// those fields indexes the messages, and a hash match is confirmed field by field: the index holds
// 16 bytes a message, not a copy of its text.
using FoldIndex = std::unordered_multimap<std::uint64_t, std::size_t>;

std::uint64_t fold_hash(const Issue& issue) {
  const std::hash<std::string_view> hash;
  std::uint64_t h = hash(issue.code);
  auto mix = [&h](std::uint64_t value) { h ^= value + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2); };
  mix(static_cast<std::uint64_t>(issue.severity));
  mix(hash(issue.pointer));
  mix(issue.offset ? *issue.offset + 1 : 0);
  mix(hash(issue.message));
  return h;
}

// The message of `messages` that `index` holds under `hash` and that is identical to `issue`.
Issue* identical_in(const FoldIndex& index, std::uint64_t hash, std::vector<Issue>& messages, const Issue& issue) {
  const auto [begin, end] = index.equal_range(hash);
  for (auto it = begin; it != end; ++it) {
    Issue& listed = messages[it->second];
    if (listed.code == issue.code && listed.severity == issue.severity && listed.pointer == issue.pointer &&
        listed.offset == issue.offset && listed.message == issue.message)
      return &listed;
  }
  return nullptr;
}
}  // namespace

void apply_policy(const IssuePolicy& policy, Report& report) {
  std::vector<Issue> kept;
  kept.reserve(report.messages.size());
  FoldIndex first_of;  // severity overrides can make issues identical that were not
  first_of.reserve(report.messages.size());
  for (Issue& issue : report.messages) {
    if (!policy.only.empty() ? !policy.only.contains(issue.code) : policy.ignore.contains(issue.code)) continue;
    if (auto found = policy.severity_override.find(issue.code); found != policy.severity_override.end())
      issue.severity = found->second;
    const std::uint64_t hash = fold_hash(issue);
    if (Issue* same = identical_in(first_of, hash, kept, issue)) {
      same->count += issue.count;
      continue;
    }
    first_of.emplace(hash, kept.size());
    kept.push_back(std::move(issue));
  }
  if (policy.max_issues != 0 && kept.size() > policy.max_issues) {
    kept.resize(policy.max_issues);
    report.truncated = true;
  }
  report.messages = std::move(kept);
  // The indices into the old list are gone: issues added from here on fold among themselves.
  report.listed_.clear();
  report.per_code_.clear();
}

void Report::add(Issue issue) {
  issue.message = valid_utf8(std::move(issue.message));
  issue.pointer = valid_utf8(std::move(issue.pointer));
  const std::uint64_t hash = fold_hash(issue);
  if (Issue* same = identical_in(listed_, hash, messages, issue)) {
    same->count += issue.count;
    return;
  }
  CodeListing& code = per_code_[issue.code];
  if (max_listed_per_code != 0 && code.listed >= max_listed_per_code) {
    if (code.unlisted != SIZE_MAX) {
      messages[code.unlisted].count += issue.count;
      return;
    }
    // The first issue past the limit keeps its place and severity, and names the rest.
    issue.message = "More issues of this code were found than a report lists (the first " +
                    std::to_string(max_listed_per_code) +
                    " distinct ones of each code); this message counts the rest, from here on "
                    "(config max-issues-per-code: 0 lists them all).";
    code.unlisted = messages.size();
  } else {
    ++code.listed;
    listed_.emplace(hash, messages.size());
  }
  messages.push_back(std::move(issue));
}

namespace {
nlohmann::ordered_json message_json(const Issue& issue) {
  nlohmann::ordered_json message;
  message["code"] = issue.code;
  message["message"] = issue.message;
  message["severity"] = static_cast<int>(issue.severity);
  if (issue.offset)
    message["offset"] = *issue.offset;
  else
    message["pointer"] = issue.pointer;
  if (issue.count > 1) message["count"] = issue.count;
  return message;
}
}  // namespace

nlohmann::ordered_json report_to_json(const Report& report) {
  nlohmann::ordered_json messages = nlohmann::ordered_json::array();
  for (const Issue& issue : report.messages) messages.push_back(message_json(issue));
  nlohmann::ordered_json json;
  json["uri"] = report.uri;
  json["mimeType"] = report.mime_type;
  json["validatorVersion"] = tool_name_and_version();
  json["issues"] = {{"numErrors", report.count(Severity::Error)},
                    {"numWarnings", report.count(Severity::Warning)},
                    {"numInfos", report.count(Severity::Information)},
                    {"numHints", report.count(Severity::Hint)},
                    {"messages", std::move(messages)},
                    {"truncated", report.truncated}};
  if (!report.info.is_null()) json["info"] = report.info;
  return json;
}

std::string report_json_text(const Report& report) {
  using Json = nlohmann::ordered_json;
  constexpr int kIndent = 2;
  // A value as dump(2) writes it where it stands `depth` levels down: its inner lines carry the
  // depth's indentation (a dumped string holds no raw newline, so every newline starts a line).
  const auto dumped = [](const Json& value, int depth) {
    const std::string text = value.dump(kIndent, ' ', false, Json::error_handler_t::replace);
    std::string out;
    out.reserve(text.size() + 64);
    for (size_t start = 0; start < text.size();) {
      const size_t line_end = std::min(text.find('\n', start), text.size() - 1) + 1;
      out.append(text, start, line_end - start);
      if (out.back() == '\n') out.append(static_cast<size_t>(depth * kIndent), ' ');
      start = line_end;
    }
    return out;
  };
  std::string out = "{\n";
  const auto member = [&](int depth, std::string_view key, const std::string& value, bool last) {
    out.append(static_cast<size_t>(depth * kIndent), ' ').append("\"").append(key).append("\": ").append(value);
    out += last ? "\n" : ",\n";
  };
  member(1, "uri", dumped(report.uri, 1), false);
  member(1, "mimeType", dumped(report.mime_type, 1), false);
  member(1, "validatorVersion", dumped(tool_name_and_version(), 1), false);
  out += "  \"issues\": {\n";
  member(2, "numErrors", std::to_string(report.count(Severity::Error)), false);
  member(2, "numWarnings", std::to_string(report.count(Severity::Warning)), false);
  member(2, "numInfos", std::to_string(report.count(Severity::Information)), false);
  member(2, "numHints", std::to_string(report.count(Severity::Hint)), false);
  if (report.messages.empty()) {
    member(2, "messages", "[]", false);
  } else {
    out += "    \"messages\": [\n";
    for (size_t i = 0; i < report.messages.size(); ++i) {
      out.append(3 * kIndent, ' ').append(dumped(message_json(report.messages[i]), 3));
      out += i + 1 < report.messages.size() ? ",\n" : "\n";
    }
    out += "    ],\n";
  }
  member(2, "truncated", report.truncated ? "true" : "false", true);
  const bool has_info = !report.info.is_null();
  out += has_info ? "  },\n" : "  }\n";
  if (has_info) member(1, "info", dumped(report.info, 1), true);
  out += "}\n";
  return out;
}

Report report_from_json(const nlohmann::ordered_json& json) {
  Report report;
  report.uri = json.at("uri").get<std::string>();
  report.mime_type = json.at("mimeType").get<std::string>();
  const nlohmann::ordered_json& issues = json.at("issues");
  report.truncated = issues.at("truncated").get<bool>();
  for (const nlohmann::ordered_json& message : issues.at("messages")) {
    Issue issue;
    issue.code = message.at("code").get<std::string>();
    issue.message = message.at("message").get<std::string>();
    const int severity = message.at("severity").get<int>();
    if (severity < 0 || severity > 3) throw std::invalid_argument("severity out of range");
    issue.severity = static_cast<Severity>(severity);
    if (message.contains("offset"))
      issue.offset = message["offset"].get<std::uint64_t>();
    else
      issue.pointer = message.at("pointer").get<std::string>();
    issue.count = message.value("count", std::uint64_t{1});
    report.messages.push_back(std::move(issue));  // as written: add() would fold nothing more
  }
  if (json.contains("info")) report.info = json["info"];
  return report;
}

}  // namespace gltf_pbr
