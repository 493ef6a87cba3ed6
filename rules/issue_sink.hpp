// The one issue sink: every step adds its findings through it, by code, with the rule's severity and
// message template (Rule::format) and a JSON pointer or a byte offset. A code the rules do not hold
// is a defect of ours (a CHECK); a disabled rule adds nothing and costs nothing more.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/report.hpp"
#include "rules/rule_set.hpp"

namespace gltf_pbr {

class IssueSink {
 public:
  IssueSink(const RuleSet& rules, Report& report) : rules_(rules), report_(report) {}
  void at(const std::string& code, const std::string& pointer, const std::vector<MessageArg>& args = {},
          const std::vector<MessageArg>& list = {});
  // Preformatted text arguments (never quoted).
  void at_text(const std::string& code, const std::string& pointer, const std::vector<std::string>& args);
  void at_offset(const std::string& code, std::uint64_t offset, const std::vector<MessageArg>& args = {});
  bool enabled(const std::string& code) const { return rules_.enabled(code); }
  // Whether the report lists no more messages of `code` (Report::max_listed_per_code): a step that
  // may find very many adds the rest with at_unlisted, counted without a message each.
  bool listing_full(const std::string& code) const { return report_.listing_full(code); }
  void at_unlisted(const std::string& code, const std::string& pointer, std::uint64_t count);
  // Whether an error-severity issue was found, shown or silenced by the configuration.
  bool found_error() const { return found_error_; }

 private:
  const Rule& rule(const std::string& code);  // CHECKs that it exists; notes an error found
  const RuleSet& rules_;
  Report& report_;
  bool found_error_ = false;
};

}  // namespace gltf_pbr
