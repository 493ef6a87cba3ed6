#include "core/report.hpp"

#include <algorithm>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "core/text.hpp"
#include "core/version.hpp"

namespace gltf_pbr {

const char* severity_name(Severity severity) {
  switch (severity) {
    case Severity::Error:
      return "error";
    case Severity::Warning:
      return "warning";
    case Severity::Information:
      return "info";
    case Severity::Hint:
      return "hint";
  }
  return "error";
}

std::size_t Report::count(Severity severity) const {
  return static_cast<std::size_t>(
      std::count_if(messages.begin(), messages.end(), [&](const Issue& issue) { return issue.severity == severity; }));
}

namespace {
std::string fold_key(const Issue& issue) {
  std::string key = issue.code;
  key += '\x1f';
  key += std::to_string(static_cast<int>(issue.severity));
  key += '\x1f';
  key += issue.pointer;
  key += '\x1f';
  key += issue.offset ? std::to_string(*issue.offset) : "-";
  key += '\x1f';
  key += issue.message;
  return key;
}
}  // namespace

void apply_policy(const IssuePolicy& policy, Report& report) {
  std::vector<Issue> kept;
  kept.reserve(report.messages.size());
  std::unordered_map<std::string, std::size_t> first_of;
  for (Issue& issue : report.messages) {
    if (!policy.only.empty() ? !policy.only.contains(issue.code) : policy.ignore.contains(issue.code)) continue;
    if (auto found = policy.severity_override.find(issue.code); found != policy.severity_override.end())
      issue.severity = found->second;
    auto [slot, inserted] = first_of.try_emplace(fold_key(issue), kept.size());
    if (!inserted) {
      kept[slot->second].count += issue.count;
      continue;
    }
    kept.push_back(std::move(issue));
  }
  if (policy.max_issues != 0 && kept.size() > policy.max_issues) {
    kept.resize(policy.max_issues);
    report.truncated = true;
  }
  report.messages = std::move(kept);
}

void Report::add(Issue issue) {
  issue.message = valid_utf8(std::move(issue.message));
  issue.pointer = valid_utf8(std::move(issue.pointer));
  messages.push_back(std::move(issue));
}

nlohmann::ordered_json report_to_json(const Report& report) {
  nlohmann::ordered_json messages = nlohmann::ordered_json::array();
  for (const Issue& issue : report.messages) {
    nlohmann::ordered_json message;
    message["code"] = issue.code;
    message["message"] = issue.message;
    message["severity"] = static_cast<int>(issue.severity);
    if (issue.offset)
      message["offset"] = *issue.offset;
    else
      message["pointer"] = issue.pointer;
    if (issue.count > 1) message["count"] = issue.count;
    messages.push_back(std::move(message));
  }
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
