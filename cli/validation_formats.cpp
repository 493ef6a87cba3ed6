#include "cli/validation_formats.hpp"

#include <algorithm>
#include <map>
#include <sstream>

#include "core/text.hpp"
#include "core/version.hpp"

namespace gltf_pbr::cli {
namespace {

struct Style {
  bool colour;
  std::string paint(const char* code, const std::string& text) const {
    return colour ? std::string("\033[") + code + "m" + text + "\033[0m" : text;
  }
};

const char* severity_colour(Severity severity) {
  switch (severity) {
    case Severity::Error: return "1;31";
    case Severity::Warning: return "33";
    case Severity::Information: return "36";
    case Severity::Hint: return "2";
  }
  return "0";
}

// -1 for messages outside /materials/N.
int material_of(const Issue& issue) {
  static const std::string prefix = "/materials/";
  if (issue.pointer.rfind(prefix, 0) != 0) return -1;
  std::size_t end = prefix.size();
  int index = 0;
  while (end < issue.pointer.size() && std::isdigit(static_cast<unsigned char>(issue.pointer[end])))
    index = index * 10 + (issue.pointer[end++] - '0');
  return end == prefix.size() ? -1 : index;
}

std::string location(const Issue& issue) {
  if (issue.offset) return std::string(1, '@').append(std::to_string(*issue.offset));  // not "@" + ...: GCC 12 -O3 -Wrestrict
  return issue.pointer.empty() ? std::string("/") : issue.pointer;
}

const char* sarif_level(Severity severity) {
  switch (severity) {
    case Severity::Error: return "error";
    case Severity::Warning: return "warning";
    case Severity::Information:
    case Severity::Hint: return "note";
  }
  return "note";
}

}  // namespace

std::string report_text(const Report& report, bool colour) {
  const Style style{colour};
  std::map<int, std::vector<const Issue*>> groups;  // -1: the document, first
  for (const Issue& issue : report.messages) groups[material_of(issue)].push_back(&issue);

  std::ostringstream out;
  // Names, URIs, pointers and messages come from the file: printable() keeps its escapes off the terminal.
  out << style.paint("1", printable(report.uri)) << ": " << report.count(Severity::Error) << " errors, "
      << report.count(Severity::Warning) << " warnings, " << report.count(Severity::Information) << " infos, "
      << report.count(Severity::Hint) << " hints" << (report.truncated ? " (truncated)" : "") << "\n";
  // Per-code totals first: on a file with thousands of issues they are the summary people read.
  // Most severe first, then most frequent. They count issues as the line above does: a folded
  // message counts every issue it stands for, as its own line's "(N times)" says.
  std::map<std::string, std::pair<Severity, std::uint64_t>> totals;
  for (const Issue& issue : report.messages) {
    auto& [severity, count] = totals.try_emplace(issue.code, issue.severity, 0).first->second;
    severity = std::min(severity, issue.severity);
    count += issue.count;
  }
  if (totals.size() > 1) {
    std::vector<std::pair<std::string, std::pair<Severity, std::uint64_t>>> ordered(totals.begin(), totals.end());
    std::stable_sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) {
      return a.second.first != b.second.first ? a.second.first < b.second.first : a.second.second > b.second.second;
    });
    out << "  by code:";
    for (std::size_t i = 0; i < ordered.size(); ++i)
      out << (i ? ", " : " ") << style.paint(severity_colour(ordered[i].second.first), ordered[i].first) << " "
          << ordered[i].second.second;
    out << "\n";
  }
  for (const auto& [material, issues] : groups) {
    if (material < 0) {
      out << "  document\n";
    } else {
      const std::string name = material < static_cast<int>(report.material_names.size()) &&
                                       !report.material_names[static_cast<std::size_t>(material)].empty()
                                   ? " \"" + printable(report.material_names[static_cast<std::size_t>(material)]) + "\""
                                   : "";
      out << "  material " << material << name << "\n";
    }
    for (const Issue* issue : issues) {
      out << "    " << style.paint(severity_colour(issue->severity), severity_name(issue->severity)) << " "
          << issue->code << " " << style.paint("2", printable(location(*issue))) << "\n      "
          << printable(issue->message);
      if (issue->count > 1) out << " (" << issue->count << " times)";
      out << "\n";
    }
  }
  return out.str();
}

nlohmann::ordered_json sarif_log(const std::vector<Report>& reports, const RuleSet& rules) {
  // The driver lists each code that occurs once, with its explanation and source as help.
  std::map<std::string, Severity> used_codes;
  for (const Report& report : reports)
    for (const Issue& issue : report.messages) used_codes.emplace(issue.code, issue.severity);
  nlohmann::ordered_json rule_list = nlohmann::ordered_json::array();
  std::map<std::string, std::size_t> rule_index;
  for (const auto& [code, severity] : used_codes) {
    nlohmann::ordered_json entry{{"id", code}};
    const Rule* rule = rules.find(code);
    const std::string description = rule && !rule->explanation.empty() ? rule->explanation
                                    : rule && !rule->message.empty()   ? rule->message
                                                                       : code;
    entry["shortDescription"] = {{"text", description}};
    if (rule && !rule->source.empty()) entry["help"] = {{"text", "Source: " + rule->source}};
    entry["defaultConfiguration"] = {{"level", sarif_level(rule ? rule->severity : severity)}};
    rule_index[code] = rule_list.size();
    rule_list.push_back(std::move(entry));
  }

  nlohmann::ordered_json results = nlohmann::ordered_json::array();
  for (const Report& report : reports) {
    for (const Issue& issue : report.messages) {
      nlohmann::ordered_json physical{{"artifactLocation", {{"uri", url_path(report.uri)}}}};
      if (issue.offset) physical["region"] = {{"byteOffset", *issue.offset}};
      nlohmann::ordered_json result{{"ruleId", issue.code},
                                    {"ruleIndex", rule_index[issue.code]},
                                    {"level", sarif_level(issue.severity)},
                                    {"message", {{"text", issue.message + " (" + location(issue) + ")"}}},
                                    {"locations", nlohmann::ordered_json::array()}};
      nlohmann::ordered_json where{{"physicalLocation", physical}};
      if (!issue.offset)
        where["logicalLocations"] = nlohmann::ordered_json::array(
            {{{"fullyQualifiedName", issue.pointer.empty() ? "/" : issue.pointer}, {"kind", "member"}}});
      result["locations"].push_back(std::move(where));
      if (issue.count > 1) result["properties"] = {{"count", issue.count}};
      results.push_back(std::move(result));
    }
  }
  nlohmann::ordered_json driver{{"name", "gltf-pbr"},
                                {"version", tool_version()},
                                {"rules", std::move(rule_list)}};
  return {{"$schema", "https://json.schemastore.org/sarif-2.1.0.json"},
          {"version", "2.1.0"},
          {"runs", nlohmann::ordered_json::array({{{"tool", {{"driver", std::move(driver)}}}, {"results", std::move(results)}}})}};
}

}  // namespace gltf_pbr::cli
