#include "rules/issue_sink.hpp"

#include "core/error.hpp"

namespace gltf_pbr {

const Rule& IssueSink::rule(const std::string& code) {
  const Rule* found = rules_.find(code);
  if (!found) check_failed("issue code in rules/*.json", code, __FILE__);
  found_error_ = found_error_ || found->severity == Severity::Error;
  return *found;
}

void IssueSink::at(const std::string& code, const std::string& pointer, const std::vector<MessageArg>& args,
                   const std::vector<MessageArg>& list) {
  const Rule& r = rule(code);
  if (r.enabled) report_.add({code, r.format(args, list), r.severity, pointer, {}, 1});
}

void IssueSink::at_unlisted(const std::string& code, const std::string& pointer, std::uint64_t count) {
  const Rule& r = rule(code);
  if (r.enabled && count > 0) report_.add({code, std::string(), r.severity, pointer, {}, count});
}

void IssueSink::at_text(const std::string& code, const std::string& pointer, const std::vector<std::string>& args) {
  const Rule& r = rule(code);
  if (r.enabled) report_.add({code, r.format(args), r.severity, pointer, {}, 1});
}

void IssueSink::at_offset(const std::string& code, std::uint64_t offset, const std::vector<MessageArg>& args) {
  const Rule& r = rule(code);
  if (r.enabled) report_.add({code, r.format(args), r.severity, "", offset, 1});
}

}  // namespace gltf_pbr
