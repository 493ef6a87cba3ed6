// `gltf-pbr validate` end to end: the three formats, the folder of reports, --fail-on, --config.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "test_support.hpp"

namespace gltf_pbr {
namespace {

using test::quoted;
using test::run_cli;

fs::path box() { return test::assets_dir() / "Box/specgloss/Box.gltf"; }
fs::path malformed(const test::ScratchDir& scratch) {
  const fs::path file = scratch / "inputs/malformed.gltf";
  fs::create_directories(file.parent_path());
  test::write_text(file, R"({"asset": {"version": "2.0"}, "materials": [)");
  return file;
}

TEST(ValidateCli, JsonReportFollowsTheKhronosSchemaAndErrorsSetExitCodeOne) {
  test::ScratchDir scratch;
  const auto result = run_cli("validate -q -f json " + quoted(malformed(scratch)), scratch);
  EXPECT_EQ(result.exit_code, 1) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["uri"], malformed(scratch).string());
  EXPECT_EQ(report["mimeType"], "model/gltf+json");
  EXPECT_GE(report["issues"]["numErrors"].get<int>(), 1);
  EXPECT_EQ(report["issues"]["messages"].size(),
            report["issues"]["numErrors"].get<std::size_t>() + report["issues"]["numWarnings"].get<std::size_t>() +
                report["issues"]["numInfos"].get<std::size_t>() + report["issues"]["numHints"].get<std::size_t>());
  for (const auto& message : report["issues"]["messages"]) {
    EXPECT_TRUE(message.contains("code") && message.contains("message") && message.contains("severity"));
    EXPECT_NE(message.contains("pointer"), message.contains("offset")) << message;
  }
}

TEST(ValidateCli, AFolderOfInputsGivesOneReportPerFileAndASummary) {
  test::ScratchDir scratch;
  malformed(scratch);
  fs::copy(test::assets_dir() / "Box/specgloss", scratch / "inputs/box");
  const fs::path out = scratch / "reports";
  const auto result = run_cli("validate -q -f json -o " + quoted(out) + " " + quoted(scratch / "inputs"), scratch);
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_TRUE(fs::exists(out / "inputs/malformed.gltf.report.json"));
  EXPECT_TRUE(fs::exists(out / "inputs/box/Box.gltf.report.json"));
  const auto summary = nlohmann::json::parse(test::read_text(out / "summary.json"));
  EXPECT_EQ(summary["files"], 2);
  EXPECT_EQ(summary["failing"], 1);
}

TEST(ValidateCli, SarifHasOneResultPerMessageWithRuleIdsAndLocations) {
  test::ScratchDir scratch;
  const fs::path input = malformed(scratch);
  const auto json = run_cli("validate -q -f json " + quoted(input), scratch);
  const auto sarif_run = run_cli("validate -q -f sarif " + quoted(input), scratch);
  EXPECT_EQ(sarif_run.exit_code, 1);
  const auto report = nlohmann::json::parse(json.out);
  const auto sarif = nlohmann::json::parse(sarif_run.out);
  EXPECT_EQ(sarif["version"], "2.1.0");
  const auto& results = sarif["runs"][0]["results"];
  ASSERT_EQ(results.size(), report["issues"]["messages"].size());
  const auto& rules = sarif["runs"][0]["tool"]["driver"]["rules"];
  for (std::size_t i = 0; i < results.size(); ++i) {
    EXPECT_EQ(results[i]["ruleId"], report["issues"]["messages"][i]["code"]);
    EXPECT_EQ(rules[results[i]["ruleIndex"].get<std::size_t>()]["id"], results[i]["ruleId"]);
    EXPECT_EQ(results[i]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"], input.string());
  }
}

TEST(ValidateCli, SarifArtifactLocationsArePercentEncodedUris) {
  // A file name with '#', '?', '%' and a space: read raw as a URI, it would name another file.
  test::ScratchDir scratch;
  fs::create_directories(scratch / "in");
  test::write_text(scratch / "in" / "a b#c?d%41.gltf", R"({"asset": {"version": "2.0"}, "materials": [)");
  const auto sarif_run = run_cli("validate -q -f sarif " + quoted(scratch / "in" / "a b#c?d%41.gltf"), scratch);
  EXPECT_EQ(sarif_run.exit_code, 1) << sarif_run.err;
  const auto sarif = nlohmann::json::parse(sarif_run.out);
  const auto& results = sarif["runs"][0]["results"];
  ASSERT_FALSE(results.empty());
  for (const auto& result : results) {
    const std::string uri = result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"];
    EXPECT_TRUE(uri.ends_with("/in/a%20b%23c%3Fd%2541.gltf")) << uri;
    EXPECT_EQ(uri.find_first_of(" #?"), std::string::npos) << uri;
  }
}

TEST(ValidateCli, FailOnSetsTheThresholdAndIgnoredCodesDoNotCount) {
  test::ScratchDir scratch;
  const fs::path input = malformed(scratch);
  const auto report = nlohmann::json::parse(run_cli("validate -q -f json " + quoted(input), scratch).out);
  std::string ignore;
  for (const auto& message : report["issues"]["messages"]) ignore += "  - " + message["code"].get<std::string>() + "\n";
  const fs::path config = scratch / "lint.yaml";
  test::write_text(config, "ignore:\n" + ignore);
  const auto quiet = run_cli("validate -q -f json --config " + quoted(config) + " " + quoted(input), scratch);
  EXPECT_EQ(quiet.exit_code, 0) << quiet.out;
  EXPECT_EQ(nlohmann::json::parse(quiet.out)["issues"]["messages"].size(), 0u);

  const fs::path demote = scratch / "demote.yaml";
  std::string overrides = "override:\n";
  for (const auto& message : report["issues"]["messages"])
    overrides += "  " + message["code"].get<std::string>() + ": hint\n";
  test::write_text(demote, overrides);
  EXPECT_EQ(run_cli("validate -q --config " + quoted(demote) + " " + quoted(input), scratch).exit_code, 0);
  EXPECT_EQ(run_cli("validate -q --fail-on hint --config " + quoted(demote) + " " + quoted(input), scratch).exit_code,
            1);
}

TEST(ValidateCli, TextGroupsByMaterialAndBadUsageIsExitCodeTwo) {
  test::ScratchDir scratch;
  const auto text = run_cli("validate " + quoted(box()), scratch);
  EXPECT_NE(text.out.find(box().string()), std::string::npos);
  // -q: only files that fail; Box has nothing at or above the default --fail-on error.
  const auto quiet = run_cli("validate -q " + quoted(box()), scratch);
  EXPECT_EQ(quiet.exit_code, 0);
  EXPECT_EQ(quiet.out, "") << "-q printed a file that does not fail";
  EXPECT_EQ(quiet.err, "");
  EXPECT_EQ(text.out.find("\033["), std::string::npos) << "colour codes in a pipe";
  EXPECT_EQ(run_cli("validate -q --only nothing " + quoted(box()), scratch).exit_code, 2);
  EXPECT_EQ(run_cli("validate -q " + quoted(scratch / "missing.gltf"), scratch).exit_code, 2);
  const fs::path config = scratch / "bad.yaml";
  test::write_text(config, "max-issues: many\n");
  const auto bad = run_cli("validate -q --config " + quoted(config) + " " + quoted(box()), scratch);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("/max-issues"), std::string::npos) << bad.err;
}

TEST(ValidateCli, ProfileChoosesTheRangesAndTheCacheKeepsProfilesApart) {
  test::ScratchDir scratch;
  const std::string textured = quoted(test::assets_dir() / "BoxTextured/metalrough/BoxTextured.gltf");
  const std::string cache = " --only materials --cache " + quoted(scratch / "cache") + " ";
  // Its white texels are plausible for the tolerant default and out of the strict range.
  const auto tolerant = run_cli("validate -q --fail-on warning" + cache + textured, scratch);
  EXPECT_EQ(tolerant.exit_code, 0) << tolerant.out << tolerant.err;
  const auto strict = run_cli("validate --fail-on warning --profile strict" + cache + textured, scratch);
  EXPECT_EQ(strict.exit_code, 1) << strict.out << strict.err;
  EXPECT_NE(strict.out.find("the strict profile's ceiling"), std::string::npos) << strict.out;
  EXPECT_EQ(run_cli("validate -q --fail-on warning" + cache + textured, scratch).exit_code, 0);
  const auto unknown = run_cli("validate -q --profile lax " + textured, scratch);
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("--profile"), std::string::npos) << unknown.err;
}

TEST(ValidateCli, TextSummaryTotalsEachCodeMostSevereFirst) {
  test::ScratchDir scratch;
  const fs::path vc = test::assets_dir() / "VC/specgloss/VC.gltf";
  const auto text = run_cli("validate " + quoted(vc), scratch);
  const std::size_t at = text.out.find("\n  by code: ");
  ASSERT_NE(at, std::string::npos) << text.out.substr(0, 400);
  const std::string line = text.out.substr(at + 12, text.out.find('\n', at + 1) - at - 12);
  // The messages listed below, counted by code, with their most severe severity.
  const std::vector<std::string> severities = {"error", "warning", "info", "hint"};
  std::map<std::string, std::pair<std::size_t, std::size_t>> listed;  // code -> (severity rank, messages)
  std::istringstream lines(text.out);
  for (std::string row; std::getline(lines, row);) {
    std::istringstream words(row);
    std::string severity, code;
    if (row.rfind("    ", 0) != 0 || row.rfind("      ", 0) == 0 || !(words >> severity >> code)) continue;
    const auto rank = static_cast<std::size_t>(std::find(severities.begin(), severities.end(), severity) -
                                               severities.begin());
    ASSERT_LT(rank, severities.size()) << row;
    auto [entry, added] = listed.try_emplace(code, rank, 0);
    entry->second.first = std::min(entry->second.first, rank);
    ++entry->second.second;
  }
  // The totals: every listed code once, with its count, most severe first, then most frequent.
  std::istringstream entries(line);
  std::vector<std::pair<std::size_t, std::size_t>> order;  // (severity rank, count) in printed order
  std::size_t codes = 0;
  for (std::string entry; std::getline(entries, entry, ',');) {
    std::istringstream words(entry);
    std::string code;
    std::size_t count = 0;
    words >> code >> count;
    ASSERT_TRUE(listed.contains(code)) << code;
    EXPECT_EQ(count, listed[code].second) << code;
    order.emplace_back(listed[code].first, count);
    ++codes;
  }
  EXPECT_EQ(codes, listed.size());
  ASSERT_GE(codes, 3u) << line;
  for (std::size_t i = 1; i < order.size(); ++i)
    EXPECT_TRUE(order[i - 1].first < order[i].first ||
                (order[i - 1].first == order[i].first && order[i - 1].second >= order[i].second))
        << "out of order at entry " << i << ": " << line;
}

TEST(ValidateCli, OnlyTakesStepListsAndLeavesTheInputsToThePositionals) {
  test::ScratchDir scratch;
  const auto result = run_cli("validate -q -f json --only materials,textures --only meshes " + quoted(box()) + " " +
                                  quoted(test::assets_dir() / "Duck/specgloss/Duck.gltf"),
                              scratch);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  const auto all = nlohmann::json::parse(result.out);
  ASSERT_EQ(all["reports"].size(), 2u);
  for (const auto& report : all["reports"])
    for (const auto& message : report["issues"]["messages"]) {
      const std::string code = message["code"];
      EXPECT_TRUE(code.rfind("PBR_", 0) == 0 || code.rfind("IMAGE_", 0) == 0 || code.rfind("MESH_", 0) == 0) << code;
    }
}

}  // namespace
}  // namespace gltf_pbr
