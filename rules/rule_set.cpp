#include "rules/rule_set.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/json_pointer.hpp"

namespace gltf_pbr {

const std::vector<std::pair<std::string, std::string>>& embedded_rule_files();  // cmake/embed.cmake

namespace {

// "/" + the escaped key, built by appending: GCC 12 -O3 warns falsely (-Wrestrict) on
// operator+(const char*, std::string&&) here.
std::string pointer_to(const std::string& key) {
  std::string pointer(1, '/');
  pointer += escape_pointer_token(key);
  return pointer;
}

Severity parse_severity(const std::string& text, const std::string& file, const std::string& pointer) {
  if (text == "0" || text == "error") return Severity::Error;
  if (text == "1" || text == "warning") return Severity::Warning;
  if (text == "2" || text == "info" || text == "information") return Severity::Information;
  if (text == "3" || text == "hint") return Severity::Hint;
  throw InputError(file, pointer, "severity must be 0-3 or error, warning, info, hint; got '" + text + "'");
}

}  // namespace

double Rule::threshold(const std::string& name) const {
  auto found = thresholds.find(name);
  if (found == thresholds.end())
    check_failed("rule has threshold", code + " has no threshold '" + name + "'", file.c_str());
  return found->second;
}

namespace {
std::string render(const MessageArg& value, bool quoted_slot) {
  return quoted_slot && value.is_string ? "'" + value.text + "'" : value.text;
}
}  // namespace

std::string Rule::format(const std::vector<MessageArg>& arguments, const std::vector<MessageArg>& list) const {
  const std::string& pattern = message;
  auto digit = [&](std::size_t at) { return at < pattern.size() && pattern[at] >= '1' && pattern[at] <= '9'; };
  std::string out;
  out.reserve(pattern.size() + 32);
  for (std::size_t i = 0; i < pattern.size();) {
    // Every slot below starts with one of these characters: the text up to the next one is copied
    // as one run (a slot test at every character was half of a million-issue run's time).
    std::size_t special = i;
    while (special < pattern.size() && pattern[special] != '(' && pattern[special] != '\'' && pattern[special] != '`' &&
           pattern[special] != '%')
      ++special;
    if (special > i) {
      out.append(pattern, i, special - i);
      i = special;
      continue;
    }
    // The list slot "('`%a`', '`%b`', '`%c`')" stands for every allowed value.
    static constexpr std::string_view list_slot = "('`%a`', '`%b`', '`%c`')";
    if (pattern.compare(i, list_slot.size(), list_slot) == 0) {
      // The reference shortens a list of more than five accessor formats ("Must be one of") to its
      // first three, "..." and its last two; lists of values ("Valid values are") stay whole.
      const bool elide = list.size() > 5 && pattern.find("Must be one of") != std::string::npos;
      out += '(';
      for (std::size_t k = 0; k < list.size(); ++k) {
        if (elide && k >= 3 && k < list.size() - 2) {
          if (k == 3) out += ", ...";
          continue;
        }
        out += (k ? ", " : "") + render(list[k], true);
      }
      out += ')';
      i += list_slot.size();
      continue;
    }
    static constexpr std::string_view long_list = "('`%1`', '`%2`', '`%3`', '`%4`', '`%5`')";
    if (pattern.compare(i, long_list.size(), long_list) == 0) {
      out += '(';
      for (std::size_t k = 0; k < list.size(); ++k) out += (k ? ", " : "") + render(list[k], true);
      out += ')';
      i += long_list.size();
      continue;
    }
    const bool quoted = pattern.compare(i, 3, "'`%") == 0;
    const std::size_t start = quoted ? i + 1 : i;
    if (pattern.compare(start, 2, "`%") == 0 && digit(start + 2) && start + 3 < pattern.size() &&
        pattern[start + 3] == '`') {
      const std::size_t slot = static_cast<std::size_t>(pattern[start + 2] - '1');
      const std::string value = slot < arguments.size() ? render(arguments[slot], quoted) : std::string();
      // A multi-line value (a parser's output) starts on its own line, with no space before it.
      if (!value.empty() && value.front() == '\n' && !out.empty() && out.back() == ' ') out.pop_back();
      out += value;
      i = start + 4 + (quoted && start + 4 < pattern.size() && pattern[start + 4] == '\'' ? 1 : 0);
      continue;
    }
    if (pattern[i] == '%' && digit(i + 1) && static_cast<std::size_t>(pattern[i + 1] - '1') < arguments.size()) {
      out += arguments[static_cast<std::size_t>(pattern[i + 1] - '1')].text;
      i += 2;
      continue;
    }
    out += pattern[i++];
  }
  // A catalogue template whose last value is empty ("... length `%1`" with "") ends without a space.
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

std::string Rule::format(const std::vector<std::string>& arguments) const {
  std::vector<MessageArg> values;
  values.reserve(arguments.size());
  for (const std::string& text : arguments) values.push_back({text, false});
  return format(values);
}

const Rule* RuleSet::find(const std::string& code) const {
  auto found = rules_.find(code);
  return found == rules_.end() ? nullptr : &found->second;
}

const Rule& RuleSet::at(const std::string& code) const {
  const Rule* rule = find(code);
  if (!rule) check_failed("rule exists", "no rule " + code, __FILE__);
  return *rule;
}

Rule& RuleSet::mutable_rule(const std::string& code) {
  auto found = rules_.find(code);
  if (found == rules_.end()) check_failed("rule exists", "no rule " + code, __FILE__);
  return found->second;
}

bool RuleSet::enabled(const std::string& code) const {
  const Rule* rule = find(code);
  return rule && rule->enabled;
}

namespace {

void read_thresholds(const nlohmann::json& thresholds, const std::string& file_name, const std::string& pointer,
                     Rule& rule) {
  if (!thresholds.is_object()) throw InputError(file_name, pointer, "expected an object of named numbers");
  for (const auto& [name, value] : thresholds.items()) {
    if (!value.is_number())
      throw InputError(file_name, pointer + "/" + escape_pointer_token(name), "a threshold must be a number");
    rule.thresholds[name] = value.get<double>();
  }
}

Severity read_severity(const nlohmann::json& severity, const std::string& file_name, const std::string& pointer) {
  if (!severity.is_number_integer() && !severity.is_string())
    throw InputError(file_name, pointer, "severity must be 0-3 or a severity name");
  return parse_severity(severity.is_number() ? std::to_string(severity.get<int>()) : severity.get<std::string>(),
                        file_name, pointer);
}

// Lays one profile's entry ({thresholds, severity, enabled, source}) over the rule.
void apply_profile_entry(const nlohmann::json& entry, const std::string& file_name, const std::string& pointer,
                         Rule& rule) {
  if (!entry.is_object()) throw InputError(file_name, pointer, "expected an object");
  for (const auto& [key, value] : entry.items()) {
    const std::string key_pointer = pointer + "/" + escape_pointer_token(key);
    if (key == "thresholds") {
      read_thresholds(value, file_name, key_pointer, rule);
    } else if (key == "severity") {
      rule.severity = read_severity(value, file_name, key_pointer);
    } else if (key == "enabled" && value.is_boolean()) {
      rule.enabled = value.get<bool>();
    } else if (key == "source" && value.is_string()) {
      rule.source = value.get<std::string>();
    } else {
      throw InputError(file_name, key_pointer,
                       "a profile entry holds thresholds, severity, enabled (true or false) and source (a string)");
    }
  }
}

// The rule as `profile` sees it. Every profile must be named, so that a new threshold cannot
// silently apply to one profile only, and every entry is read, so that an error in the other
// profile's entry is found whichever profile is used.
Rule rule_for_profile(const Rule& rule, const nlohmann::json& profiles, LintProfile profile,
                      const std::string& file_name, const std::string& pointer) {
  if (!profiles.is_object()) throw InputError(file_name, pointer, "expected an object of profile name to values");
  for (const auto& item : profiles.items()) {
    const std::string& name = item.key();  // a named variable: clang 14 cannot capture a structured binding
    if (std::ranges::none_of(kLintProfiles, [&](LintProfile each) { return name == rule_profile_name(each); }))
      throw InputError(file_name, pointer + "/" + escape_pointer_token(name),
                       "unknown lint profile '" + name + "' (expected tolerant or strict)");
  }
  Rule chosen;
  for (const LintProfile each : kLintProfiles) {
    const char* name = rule_profile_name(each);
    if (!profiles.contains(name))
      throw InputError(file_name, pointer, std::string("no entry for the ") + name + " profile");
    Rule variant = rule;
    apply_profile_entry(profiles[name], file_name, pointer + "/" + name, variant);
    variant.profile = each;
    if (each == profile) chosen = std::move(variant);
  }
  return chosen;
}

}  // namespace

const char* rule_profile_name(LintProfile profile) { return profile == LintProfile::Strict ? "strict" : "tolerant"; }

void RuleSet::add_from_json(const std::string& file_name, const std::string& text, LintProfile profile) {
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(file_name, "", std::string("not valid JSON: ") + error.what());
  }
  if (!document.is_object() || !document.contains("rules") || !document["rules"].is_array())
    throw InputError(file_name, "/rules", "expected an array of rules");
  const auto& list = document["rules"];
  for (std::size_t index = 0; index < list.size(); ++index) {
    const std::string pointer = "/rules/" + std::to_string(index);
    const auto& entry = list[index];
    if (!entry.is_object() || !entry.contains("code") || !entry["code"].is_string())
      throw InputError(file_name, pointer, "a rule needs a string 'code'");
    Rule rule;
    rule.file = file_name;
    rule.code = entry["code"];
    if (rules_.contains(rule.code)) throw InputError(file_name, pointer + "/code", rule.code + " is defined twice");
    rule.severity = read_severity(entry.value("severity", nlohmann::json("error")), file_name, pointer + "/severity");
    rule.enabled = entry.value("enabled", true);
    if (entry.contains("thresholds")) read_thresholds(entry["thresholds"], file_name, pointer + "/thresholds", rule);
    rule.message = entry.value("message", "");
    rule.explanation = entry.value("explanation", "");
    rule.source = entry.value("source", "");
    if (entry.contains("profiles"))
      rule = rule_for_profile(rule, entry["profiles"], profile, file_name, pointer + "/profiles");
    rules_.emplace(rule.code, std::move(rule));
  }
}

const RuleSet& builtin_rules(LintProfile profile) {
  static_assert(kLintProfiles[0] == LintProfile::Tolerant && kLintProfiles[1] == LintProfile::Strict);
  const auto index = static_cast<std::size_t>(profile);
  if (index >= kLintProfiles.size()) check_failed("known lint profile", std::to_string(index), __FILE__);
  static const std::array<RuleSet, kLintProfiles.size()> rules = [] {
    std::array<RuleSet, kLintProfiles.size()> sets;
    for (std::size_t i = 0; i < kLintProfiles.size(); ++i)
      for (const auto& [name, text] : embedded_rule_files())
        sets[i].add_from_json("rules/" + name, text, kLintProfiles[i]);
    return sets;
  }();
  return rules[index];
}

const std::string& builtin_rules_text() {
  static const std::string text = [] {
    std::string all;
    for (const auto& [name, content] : embedded_rule_files()) all += name + '\0' + content + '\0';
    return all;
  }();
  return text;
}

void apply_user_config(const std::filesystem::path& config_file, RuleSet& rules, IssuePolicy& policy) {
  const std::string file = config_file.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw InputError(file, "", "cannot read the config file: " + unreadable_reason(config_file));
  } catch (const YAML::Exception& error) {
    throw InputError(file, "", std::string("not valid YAML: ") + error.what());
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw InputError(file, "", "expected a mapping at the top level");

  auto codes = [&](const char* key) {
    std::set<std::string> result;
    const YAML::Node list = root[key];
    if (!list) return result;
    if (!list.IsSequence()) throw InputError(file, std::string("/") + key, "expected a list of issue codes");
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].IsScalar())
        throw InputError(file, "/" + std::string(key) + "/" + std::to_string(i), "expected an issue code");
      result.insert(list[i].as<std::string>());
    }
    return result;
  };

  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    const std::string pointer = pointer_to(key);
    const YAML::Node& value = entry.second;
    const auto whole_number = [&] {
      long long count = -1;
      try {
        count = value.as<long long>();
      } catch (const YAML::Exception&) {
      }
      if (count < 0) throw InputError(file, pointer, key + " must be a whole number, 0 for no limit");
      return static_cast<std::uint64_t>(count);
    };
    if (key == "max-issues") {
      policy.max_issues = whole_number();
    } else if (key == "max-issues-per-code") {  // ours
      policy.max_listed_per_code = whole_number();
    } else if (key == "ignore") {
      policy.ignore = codes("ignore");
    } else if (key == "only") {
      policy.only = codes("only");
    } else if (key == "override") {
      if (!value.IsMap()) throw InputError(file, pointer, "expected a map of issue code to severity");
      for (const auto& item : value) {
        const std::string code = item.first.as<std::string>();
        policy.severity_override[code] =
            parse_severity(item.second.as<std::string>(), file, pointer + "/" + escape_pointer_token(code));
      }
    } else if (key == "thresholds") {
      if (!value.IsMap()) throw InputError(file, pointer, "expected a map of rule code to {name: number}");
      for (const auto& item : value) {
        const std::string code = item.first.as<std::string>();
        const std::string code_pointer = pointer + "/" + escape_pointer_token(code);
        if (!rules.find(code)) throw InputError(file, code_pointer, "no rule has the code " + code);
        Rule& rule = rules.mutable_rule(code);
        if (!item.second.IsMap()) throw InputError(file, code_pointer, "expected a map of threshold name to number");
        for (const auto& threshold : item.second) {
          const std::string name = threshold.first.as<std::string>();
          const std::string name_pointer = code_pointer + "/" + escape_pointer_token(name);
          if (!rule.thresholds.contains(name)) {
            std::string known;
            for (const auto& [known_name, unused] : rule.thresholds) known += (known.empty() ? "" : ", ") + known_name;
            throw InputError(file, name_pointer, code + " has no threshold '" + name + "' (it has: " + known + ")");
          }
          try {
            rule.thresholds[name] = threshold.second.as<double>();
            rule.configured = true;
          } catch (const YAML::Exception&) {
            throw InputError(file, name_pointer, "a threshold must be a number");
          }
        }
      }
    } else {
      throw InputError(file, pointer,
                       "unknown key (expected max-issues, max-issues-per-code, ignore, only, override or thresholds)");
    }
  }
  if (!policy.ignore.empty() && !policy.only.empty())
    throw InputError(file, "/only", "'only' cannot be used along with 'ignore'");
  // Naming a rule in `only` or `override` asks for its issues: a rule that is off by default
  // (MESH_EDGE_BORDER; PBR_ALBEDO_TOO_BRIGHT in the tolerant profile) is turned on.
  for (const std::string& code : policy.only)
    if (rules.find(code)) rules.mutable_rule(code).enabled = true;
  for (const auto& [code, severity] : policy.severity_override)
    if (rules.find(code)) rules.mutable_rule(code).enabled = true;
  // Checks whose every code is silenced need not run.
  for (const auto& [code, rule] : rules.all()) {
    const bool silenced = policy.only.empty() ? policy.ignore.contains(code) : !policy.only.contains(code);
    if (silenced) rules.mutable_rule(code).enabled = false;
  }
}

}  // namespace gltf_pbr
