// The rule set as data. Every rules/*.json file ships inside the executable (embedded at build time)
// and holds {"rules": [{code, severity, enabled, thresholds, profiles, message, explanation, source}]}.
// A rule whose ranges depend on the lint profile holds, under "profiles", one entry per profile
// ({thresholds, severity, enabled, source}, each optional) laid over its other fields; a rule set is
// read for one profile. A user config file in the Khronos validator's YAML shape overrides it.
#pragma once
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/report.hpp"
#include "gltf_pbr/gltf_pbr.hpp"  // LintProfile

namespace gltf_pbr {

inline constexpr LintProfile kDefaultLintProfile = LintProfile::Tolerant;
// Every profile, in the order of the enumeration (builtin_rules indexes its sets by the value).
inline constexpr std::array<LintProfile, 2> kLintProfiles{LintProfile::Tolerant, LintProfile::Strict};
// The profile's name in the rule data, the tool's --profile and messages ("tolerant", "strict").
const char* rule_profile_name(LintProfile profile);

// One value for a message template. A string is quoted ('text') where the template quotes its slot,
// as the Khronos catalogue writes '`%1`'; numbers and preformatted text never are.
struct MessageArg {
  std::string text;
  bool is_string = false;
};

struct Rule {
  std::string code;
  Severity severity = Severity::Error;
  bool enabled = true;                       // off: the check does not run at all (and costs nothing)
  std::map<std::string, double> thresholds;  // named numbers the check compares against
  std::string message;                       // message template: placeholders %1, %2, ... or `%1` (catalogue)
  std::string explanation;                   // one line: why this is implausible or wrong
  std::string source;                        // where the threshold comes from
  std::string file;                          // the rules/ file it came from (for error messages)
  // The profile its values were read for; empty when they are the same in every profile. Messages
  // of profiled rules name it, so a reader knows which range judged.
  std::optional<LintProfile> profile;
  bool configured = false;  // a user config changed its thresholds (messages say so)

  // The named threshold; a missing name is a defect of the shipped rules, so it is a CHECK.
  double threshold(const std::string& name) const;
  // The one message formatter of every step. Fills %N with arguments[N-1] (one past them stays as
  // it is), and the catalogue's forms (rules/structure.json, Khronos ISSUES.md): `%N` with the value
  // (empty past them), '`%N`' with it quoted when it is a string, and the list slots
  // "('`%a`', '`%b`', '`%c`')" and "('`%1`', ..., '`%5`')" with every entry of `list`.
  std::string format(const std::vector<MessageArg>& arguments, const std::vector<MessageArg>& list = {}) const;
  // Preformatted text arguments, never quoted.
  std::string format(const std::vector<std::string>& arguments) const;
};

class RuleSet {
 public:
  const Rule* find(const std::string& code) const;
  const Rule& at(const std::string& code) const;  // CHECKs that the code exists
  bool enabled(const std::string& code) const;    // false for unknown codes too
  const std::map<std::string, Rule>& all() const { return rules_; }

  // Parses one rules file's text for `profile`; later files may not redefine a code.
  void add_from_json(const std::string& file_name, const std::string& text, LintProfile profile = kDefaultLintProfile);
  Rule& mutable_rule(const std::string& code);

 private:
  std::map<std::string, Rule> rules_;
};

// Every rules/*.json of the source tree, as embedded into the build, read for `profile`.
const RuleSet& builtin_rules(LintProfile profile = kDefaultLintProfile);
// Those files' names and text, one after another: what a cached result's key holds of the rules.
const std::string& builtin_rules_text();

// Reads a user config (YAML or JSON; JSON is YAML) and applies it. The Khronos shape:
//   max-issues: 10            ignore: [CODE, ...]      only: [CODE, ...]
//   override: {CODE: 0}       (0 error, 1 warning, 2 info, 3 hint; names are accepted too)
// and ours:
//   thresholds: {CODE: {name: value}}
// `ignore` and `only` also switch the checks themselves off, so ignored work is not done; a rule
// named in `only` or `override` is switched on even where it is off by default.
// Bad input throws InputError naming the file, the JSON pointer and the reason.
void apply_user_config(const std::filesystem::path& config_file, RuleSet& rules, IssuePolicy& policy);

}  // namespace gltf_pbr
