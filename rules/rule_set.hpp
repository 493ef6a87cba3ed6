// The rule set as data. Every rules/*.json file ships inside the executable (embedded at build time)
// and holds {"rules": [{code, severity, enabled, thresholds, message, explanation, source}]}. A user
// config file in the Khronos validator's YAML shape overrides it.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/report.hpp"

namespace gltf_pbr {

struct Rule {
  std::string code;
  Severity severity = Severity::Error;
  bool enabled = true;                       // off: the check does not run at all (and costs nothing)
  std::map<std::string, double> thresholds;  // named numbers the check compares against
  std::string message;                       // message template, placeholders %1, %2, ...
  std::string explanation;                   // one line: why this is implausible or wrong
  std::string source;                        // where the threshold comes from
  std::string file;                          // the rules/ file it came from (for error messages)

  // The named threshold; a missing name is a defect of the shipped rules, so it is a CHECK.
  double threshold(const std::string& name) const;
  // The message with %1, %2, ... replaced by `arguments` (a placeholder past them stays as it is).
  std::string format(const std::vector<std::string>& arguments) const;
};

class RuleSet {
 public:
  const Rule* find(const std::string& code) const;
  const Rule& at(const std::string& code) const;  // CHECKs that the code exists
  bool enabled(const std::string& code) const;    // false for unknown codes too
  const std::map<std::string, Rule>& all() const { return rules_; }

  // Parses one rules file's text; later files may not redefine a code.
  void add_from_json(const std::string& file_name, const std::string& text);
  Rule& mutable_rule(const std::string& code);

 private:
  std::map<std::string, Rule> rules_;
};

// Every rules/*.json of the source tree, as embedded into the build.
const RuleSet& builtin_rules();
// Those files' names and text, one after another: what a cached result's key holds of the rules.
const std::string& builtin_rules_text();

// Reads a user config (YAML or JSON; JSON is YAML) and applies it. The Khronos shape:
//   max-issues: 10            ignore: [CODE, ...]      only: [CODE, ...]
//   override: {CODE: 0}       (0 error, 1 warning, 2 info, 3 hint; names are accepted too)
// and ours:
//   thresholds: {CODE: {name: value}}
// `ignore` and `only` also switch the checks themselves off, so ignored work is not done.
// Bad input throws InputError naming the file, the JSON pointer and the reason.
void apply_user_config(const std::filesystem::path& config_file, RuleSet& rules, IssuePolicy& policy);

}  // namespace gltf_pbr
