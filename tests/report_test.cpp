// The report model and the user config: what --config does to a report, and the Khronos schema.
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.hpp"
#include "core/report.hpp"
#include "rules/rule_set.hpp"
#include "test_support.hpp"

namespace gltf_pbr {
namespace {

Issue issue(const std::string& code, const std::string& pointer, Severity severity = Severity::Error,
            const std::string& message = "m") {
  return Issue{code, message, severity, pointer, std::nullopt, 1};
}

RuleSet two_rules() {
  RuleSet rules;
  rules.add_from_json("rules/test.json", R"({"rules": [
    {"code": "PBR_A", "severity": "warning", "thresholds": {"min": 0.02, "max": 0.08},
     "explanation": "a", "source": "s"},
    {"code": "PBR_B", "severity": 2}]})");
  return rules;
}

fs::path write_config(const test::ScratchDir& dir, const std::string& text) {
  const fs::path path = dir / "config.yaml";
  std::ofstream(path) << text;
  return path;
}

// The report text written a message at a time is the text of the whole JSON document, whatever
// the report holds: no messages, offsets, counts, bytes that are not UTF-8, control characters,
// quotes, multi-line messages, and an info block nested several levels or none.
TEST(ReportText, WrittenAMessageAtATimeEqualsTheDocumentsDump) {
  auto document_text = [](const Report& report) {
    return report_to_json(report).dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  };
  Report empty;
  EXPECT_EQ(report_json_text(empty), document_text(empty));

  Report full;
  full.uri = "dir/na\xffme \"quoted\".gltf";  // not UTF-8: written as U+FFFD either way
  full.mime_type = "model/gltf+json";
  full.add(issue("A", "/materials/0", Severity::Error, "line one\nline two\t\u0001 <b>&"));
  full.add(issue("A", "/materials/0", Severity::Error, "line one\nline two\t\u0001 <b>&"));  // count 2
  full.add(Issue{"B", "byte offset", Severity::Warning, "", std::uint64_t{12}, 1});
  full.add(issue("C", "/nodes/3", Severity::Hint, "caf\xc3\xa9 \xe2\x80\x94 \xc3"));
  full.truncated = true;
  full.info = {{"version", "2.0"},
               {"resources", {{{"pointer", "/buffers/0"}, {"image", {{"width", 4}}}}}},
               {"empty", nlohmann::ordered_json::object()},
               {"none", nlohmann::ordered_json::array()}};
  EXPECT_EQ(report_json_text(full), document_text(full));

  Report no_info = full;
  no_info.info = nullptr;
  EXPECT_EQ(report_json_text(no_info), document_text(no_info));
}

TEST(IssuePolicy, IdenticalRepeatsFoldIntoOneMessageWithACountWhereTheyFirstOccurred) {
  Report report;
  report.add(issue("A", "/materials/0"));
  report.add(issue("B", "/materials/1"));
  report.add(issue("A", "/materials/0"));
  report.add(issue("A", "/materials/2"));  // another place: not identical
  report.add(issue("A", "/materials/0"));
  apply_policy({}, report);
  ASSERT_EQ(report.messages.size(), 3u);
  EXPECT_EQ(report.messages[0].code, "A");
  EXPECT_EQ(report.messages[0].count, 3u);
  EXPECT_EQ(report.messages[1].code, "B");
  EXPECT_EQ(report.messages[2].pointer, "/materials/2");
  EXPECT_EQ(report.messages[2].count, 1u);
}

TEST(IssuePolicy, AReportListsAFixedNumberOfMessagesPerCodeAndCountsTheRest) {
  Report report;
  report.max_listed_per_code = 3;
  for (int i = 0; i < 100000; ++i) report.add(issue("A", "/a/" + std::to_string(i)));
  report.add(issue("B", "/b", Severity::Warning));
  report.add(issue("A", "/a/1"));  // identical to a listed one: folds into it, not into the rest
  ASSERT_EQ(report.messages.size(), 5u);  // three A, the one that counts the rest of A, B
  EXPECT_EQ(report.messages[1].count, 2u);
  const Issue& rest = report.messages[3];
  EXPECT_EQ(rest.code, "A");
  EXPECT_EQ(rest.pointer, "/a/3");  // where the unlisted ones start
  EXPECT_EQ(rest.count, 100000u - 3u);
  EXPECT_NE(rest.message.find("the first 3 distinct ones of each code"), std::string::npos) << rest.message;
  EXPECT_EQ(report.count(Severity::Error), 100001u);  // every issue found is counted
  EXPECT_EQ(report.count(Severity::Warning), 1u);
  // After the policy the list is final; issues added later fold among themselves.
  apply_policy({}, report);
  EXPECT_EQ(report.messages.size(), 5u);
  report.add(issue("C", "/c"));
  report.add(issue("C", "/c"));
  EXPECT_EQ(report.messages.back().count, 2u);

  Report all;
  all.max_listed_per_code = 0;  // max-issues-per-code: 0 lists them all
  for (int i = 0; i < 2000; ++i) all.add(issue("A", "/a/" + std::to_string(i)));
  EXPECT_EQ(all.messages.size(), 2000u);
}

TEST(IssuePolicy, IgnoreOnlyOverrideAndMaxIssuesActAsTheKhronosConfigDoes) {
  Report report;
  for (int i = 0; i < 4; ++i) report.add(issue("A", "/a/" + std::to_string(i)));
  report.add(issue("B", "/b", Severity::Warning));
  Report ignored = report, only = report, overridden = report, truncated = report;

  apply_policy(IssuePolicy{0, {"A"}, {}, {}}, ignored);
  ASSERT_EQ(ignored.messages.size(), 1u);
  EXPECT_EQ(ignored.messages[0].code, "B");

  apply_policy(IssuePolicy{0, {}, {"A"}, {}}, only);
  EXPECT_EQ(only.messages.size(), 4u);
  EXPECT_EQ(only.count(Severity::Warning), 0u);

  apply_policy(IssuePolicy{0, {}, {}, {{"B", Severity::Error}}}, overridden);
  EXPECT_EQ(overridden.count(Severity::Error), 5u);

  apply_policy(IssuePolicy{2, {}, {}, {}}, truncated);
  EXPECT_EQ(truncated.messages.size(), 2u);
  EXPECT_TRUE(truncated.truncated);
}

TEST(ReportJson, FollowsTheKhronosSchemaWithPointerOrOffsetAndCountOnlyWhenFolded) {
  Report report;
  report.uri = "a.glb";
  report.mime_type = "model/gltf-binary";
  report.add(issue("A", "/x", Severity::Warning));
  report.add(Issue{"GLB_CHUNK_TOO_BIG", "m", Severity::Error, "", 20, 1});
  report.add(issue("C", "/y", Severity::Hint));
  report.messages[0].count = 4;
  const auto json = report_to_json(report);
  EXPECT_EQ(json["uri"], "a.glb");
  EXPECT_EQ(json["mimeType"], "model/gltf-binary");
  EXPECT_EQ(json["issues"]["numErrors"], 1);
  EXPECT_EQ(json["issues"]["numWarnings"], 4);  // issues found, as the reference counts them: folding hides none
  EXPECT_EQ(json["issues"]["numInfos"], 0);
  EXPECT_EQ(json["issues"]["numHints"], 1);
  EXPECT_EQ(json["issues"]["truncated"], false);
  const auto& messages = json["issues"]["messages"];
  EXPECT_EQ(messages[0]["count"], 4);
  EXPECT_EQ(messages[0]["pointer"], "/x");
  EXPECT_EQ(messages[1]["offset"], 20);
  EXPECT_FALSE(messages[1].contains("pointer"));
  EXPECT_FALSE(messages[2].contains("count"));
  EXPECT_FALSE(json.contains("info"));  // never filled: omitted, as the reference does
}

TEST(RuleSet, ReadsSeverityByNameOrNumberThresholdsAndRefusesDuplicates) {
  RuleSet rules = two_rules();
  EXPECT_EQ(rules.at("PBR_A").severity, Severity::Warning);
  EXPECT_EQ(rules.at("PBR_B").severity, Severity::Information);
  EXPECT_DOUBLE_EQ(rules.at("PBR_A").threshold("max"), 0.08);
  EXPECT_THROW(rules.add_from_json("rules/again.json", R"({"rules": [{"code": "PBR_A"}]})"), InputError);
  try {
    rules.add_from_json("rules/bad.json", R"({"rules": [{"code": "PBR_C", "thresholds": {"max": "high"}}]})");
    FAIL() << "a string threshold was accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(error.pointer, "/rules/0/thresholds/max");
  }
}

TEST(RuleSet, EveryBuiltInRuleHasAnExplanationAndASourceInEveryProfile) {
  for (const LintProfile profile : {LintProfile::Tolerant, LintProfile::Strict})
    for (const auto& [code, rule] : builtin_rules(profile).all()) {
      if (rule.file == "rules/structure.json") continue;  // the Khronos catalogue: message templates
      EXPECT_FALSE(rule.explanation.empty()) << code;
      EXPECT_FALSE(rule.source.empty()) << code << " (" << rule_profile_name(profile) << ")";
    }
}

TEST(RuleSet, AProfileEntryIsLaidOverTheRuleForItsProfileOnly) {
  const std::string text = R"({"rules": [{"code": "PBR_A", "severity": "warning", "thresholds": {"shared": 1},
    "profiles": {"tolerant": {"thresholds": {"min": 0.01}, "severity": "info", "enabled": false},
                 "strict": {"thresholds": {"min": 0.02}, "source": "strict source"}},
    "source": "rule source"}, {"code": "PBR_B", "thresholds": {"min": 5}}]})";
  RuleSet tolerant, strict;
  tolerant.add_from_json("rules/p.json", text, LintProfile::Tolerant);
  strict.add_from_json("rules/p.json", text, LintProfile::Strict);
  EXPECT_DOUBLE_EQ(tolerant.at("PBR_A").threshold("min"), 0.01);
  EXPECT_DOUBLE_EQ(strict.at("PBR_A").threshold("min"), 0.02);
  EXPECT_DOUBLE_EQ(strict.at("PBR_A").threshold("shared"), 1.0);
  EXPECT_EQ(tolerant.at("PBR_A").severity, Severity::Information);
  EXPECT_EQ(strict.at("PBR_A").severity, Severity::Warning);
  EXPECT_FALSE(tolerant.enabled("PBR_A"));
  EXPECT_TRUE(strict.enabled("PBR_A"));
  EXPECT_EQ(tolerant.at("PBR_A").source, "rule source");
  EXPECT_EQ(strict.at("PBR_A").source, "strict source");
  EXPECT_EQ(strict.at("PBR_A").profile, LintProfile::Strict);
  EXPECT_EQ(strict.at("PBR_B").profile, std::nullopt);  // the same in every profile: messages need not say
}

TEST(RuleSet, ProfileEntriesMustNameEveryKnownProfileAndNothingElse) {
  const auto pointer_of_error = [](const std::string& profiles) {
    RuleSet rules;
    try {
      rules.add_from_json("rules/bad.json", R"({"rules": [{"code": "PBR_A", "profiles": )" + profiles + "}]}");
    } catch (const InputError& error) {
      return error.pointer + ": " + error.reason;
    }
    return std::string("accepted");
  };
  EXPECT_EQ(pointer_of_error(R"({"tolerant": {}})"), "/rules/0/profiles: no entry for the strict profile");
  EXPECT_EQ(pointer_of_error(R"({"tolerant": {}, "strict": {}, "lax": {}})"),
            "/rules/0/profiles/lax: unknown lint profile 'lax' (expected tolerant or strict)");
  EXPECT_EQ(pointer_of_error(R"({"tolerant": {"message": "x"}, "strict": {}})").substr(0, 35),
            "/rules/0/profiles/tolerant/message:");
  EXPECT_EQ(pointer_of_error(R"({"tolerant": {"thresholds": {"min": "low"}}, "strict": {}})"),
            "/rules/0/profiles/tolerant/thresholds/min: a threshold must be a number");
  EXPECT_EQ(pointer_of_error(R"({"tolerant": {}, "strict": {}})"), "accepted");
}

TEST(UserConfig, KhronosShapeSetsThePolicyAndThresholdsChangeTheRules) {
  test::ScratchDir dir;
  RuleSet rules = two_rules();
  IssuePolicy policy;
  apply_user_config(write_config(dir, "max-issues: 10\n"
                                      "max-issues-per-code: 50\n"
                                      "ignore:\n  - PBR_B\n"
                                      "override:\n  PBR_A: 0\n  OTHER: hint\n"
                                      "thresholds:\n  PBR_A: {min: 0.01}\n"),
                    rules, policy);
  EXPECT_EQ(policy.max_issues, 10u);
  EXPECT_EQ(policy.max_listed_per_code, 50u);
  EXPECT_TRUE(policy.ignore.contains("PBR_B"));
  EXPECT_EQ(policy.severity_override.at("PBR_A"), Severity::Error);
  EXPECT_EQ(policy.severity_override.at("OTHER"), Severity::Hint);
  EXPECT_DOUBLE_EQ(rules.at("PBR_A").threshold("min"), 0.01);
  EXPECT_DOUBLE_EQ(rules.at("PBR_A").threshold("max"), 0.08);
  EXPECT_TRUE(rules.enabled("PBR_A"));
  EXPECT_FALSE(rules.enabled("PBR_B"));  // ignored checks do not run
}

TEST(UserConfig, BadConfigsNameTheFileThePointerAndTheReason) {
  test::ScratchDir dir;
  const std::vector<std::pair<std::string, std::string>> cases{
      {"max-issues: -3\n", "/max-issues"},
      {"max-issues-per-code: some\n", "/max-issues-per-code"},
      {"ignore: PBR_A\n", "/ignore"},
      {"override:\n  PBR_A: 7\n", "/override/PBR_A"},
      {"thresholds:\n  PBR_Z: {min: 1}\n", "/thresholds/PBR_Z"},
      {"thresholds:\n  PBR_A: {lowest: 1}\n", "/thresholds/PBR_A/lowest"},
      {"thresholds:\n  PBR_A: {min: low}\n", "/thresholds/PBR_A/min"},
      {"ignore: [PBR_A]\nonly: [PBR_B]\n", "/only"},
      {"colour: red\n", "/colour"},
  };
  for (const auto& [text, pointer] : cases) {
    RuleSet rules = two_rules();
    IssuePolicy policy;
    const fs::path path = write_config(dir, text);
    try {
      apply_user_config(path, rules, policy);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& error) {
      EXPECT_EQ(error.file, path.string()) << text;
      EXPECT_EQ(error.pointer, pointer) << text;
      EXPECT_FALSE(error.reason.empty());
    }
  }
}

TEST(UserConfig, TheKhronosExampleConfigIsAccepted) {
  RuleSet rules = two_rules();
  IssuePolicy policy;
  // Its example has both ignore and only, which its own comment forbids; drop `only`.
  const std::string example = test::read_text(test::shared_dir() / "validator-suite/reference/config-example.yaml");
  test::ScratchDir dir;
  const std::size_t only_at = example.find("# List of only");
  const std::size_t override_at = example.find("# Map of overridden");
  apply_user_config(write_config(dir, example.substr(0, only_at) + example.substr(override_at)), rules, policy);
  EXPECT_EQ(policy.max_issues, 10u);
  EXPECT_TRUE(policy.ignore.contains("UNEXPECTED_PROPERTY"));
  EXPECT_EQ(policy.severity_override.at("ACCESSOR_INDEX_TRIANGLE_DEGENERATE"), Severity::Error);
}

}  // namespace
}  // namespace gltf_pbr
