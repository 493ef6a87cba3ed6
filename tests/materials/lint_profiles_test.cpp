// The two lint profiles of rules/materials.json: the tolerant default warns only where the strict
// profile also warns, passes reference textures that the strict one flags, and every message names
// the profile and the bound that judged.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "material_test_support.hpp"
#include "test_support.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

using namespace test;  // the builders and report queries of the test support headers

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// For a rule of both profiles, whether the tolerant value of `name` lets through all the strict
// value does: floors (min_*) no higher, ceilings and shares (max_*, min_coverage_percent) no lower.
bool looser_or_equal(const std::string& name, double tolerant, double strict) {
  if (name == "min_coverage_percent") return tolerant >= strict;  // fewer texels failing is reported
  if (name.starts_with("min_")) return tolerant <= strict;
  return tolerant >= strict;
}

TEST(LintProfiles, TolerantRangesContainTheStrictOnesRuleByRule) {
  const RuleSet& tolerant = builtin_rules(LintProfile::Tolerant);
  const RuleSet& strict = builtin_rules(LintProfile::Strict);
  int profiled = 0;
  for (const auto& [code, strict_rule] : strict.all()) {
    const Rule& tolerant_rule = tolerant.at(code);
    EXPECT_EQ(tolerant_rule.profile.has_value(), strict_rule.profile.has_value()) << code;
    if (!strict_rule.profile) continue;
    ++profiled;
    EXPECT_TRUE(!tolerant_rule.enabled || strict_rule.enabled) << code << ": on in tolerant only";
    EXPECT_GE(static_cast<int>(tolerant_rule.severity), static_cast<int>(strict_rule.severity))
        << code << ": more severe in tolerant";
    ASSERT_EQ(tolerant_rule.thresholds.size(), strict_rule.thresholds.size()) << code;
    for (const auto& [name, value] : strict_rule.thresholds)
      EXPECT_TRUE(looser_or_equal(name, tolerant_rule.threshold(name), value))
          << code << " " << name << ": tolerant " << tolerant_rule.threshold(name) << ", strict " << value;
  }
  EXPECT_GE(profiled, 8);  // every range rule of DESIGN.md's plausibility table
}

// Warnings and errors of the material step, as (code, pointer).
std::set<std::pair<std::string, std::string>> problem_places(const Report& report) {
  std::set<std::pair<std::string, std::string>> places;
  for (const Issue& issue : problems(report)) places.emplace(issue.code, issue.pointer);
  return places;
}

TEST(LintProfiles, TolerantWarnsOnlyWhereStrictDoesOnEverySharedAsset) {
  ValidateOptions options;
  options.steps = {ValidationStep::Materials};
  int files = 0, tolerant_files = 0, strict_files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(test::assets_dir())) {
    const std::string extension = entry.path().extension().string();
    if (extension != ".gltf" && extension != ".glb") continue;
    ++files;
    const std::string name = fs::relative(entry.path(), test::assets_dir()).string();
    const auto tolerant =
        problem_places(validate_file(entry.path(), name, builtin_rules(LintProfile::Tolerant), {}, options));
    const auto strict =
        problem_places(validate_file(entry.path(), name, builtin_rules(LintProfile::Strict), {}, options));
    for (const auto& place : tolerant)
      EXPECT_TRUE(strict.contains(place))
          << name << ": " << place.first << " at " << place.second << " in tolerant only";
    tolerant_files += !tolerant.empty();
    strict_files += !strict.empty();
  }
  EXPECT_GE(files, 20);
  EXPECT_LT(tolerant_files, strict_files);
}

TEST(LintProfiles, AReferenceTexturePassesTheDefaultAndStrictNamesItsWhite) {
  const fs::path box = test::assets_dir() / "BoxTextured/metalrough/BoxTextured.gltf";
  ValidateOptions options;
  options.steps = {ValidationStep::Materials};
  const Report tolerant = validate_file(box, "BoxTextured.gltf", builtin_rules(), {}, options);
  EXPECT_TRUE(problems(tolerant).empty()) << describe(problems(tolerant));
  const Report strict = validate_file(box, "BoxTextured.gltf", builtin_rules(LintProfile::Strict), {}, options);
  const auto bright = issues_with(strict, "PBR_ALBEDO_TOO_BRIGHT");
  ASSERT_EQ(bright.size(), 1u) << describe(strict.messages);
  EXPECT_TRUE(contains(bright[0].message, "brighter than 0.900 (linear luminance, sRGB 243; the strict profile's"))
      << bright[0].message;
}

TEST(LintProfiles, MessagesNameTheProfileAndTheBoundThatJudged) {
  AssetBuilder builder;
  builder.metal_rough(glm::vec4(0.008f, 0.008f, 0.008f, 1.0f), 0.0, 0.5);  // sRGB 22: dark, not black
  builder.metal_rough(glm::vec4(0.001f, 0.001f, 0.001f, 1.0f), 0.0, 0.5);  // sRGB 3: near black
  builder.metal_rough(glm::vec4(0.8f, 0.0f, 0.0f, 1.0f), 1.0, 0.5);        // red metal, mean F0 0.27
  const Report tolerant = validate_in_memory(builder.asset(), builtin_rules(LintProfile::Tolerant));
  const Report strict = validate_in_memory(builder.asset(), builtin_rules(LintProfile::Strict));

  const auto dark_tolerant = issues_with(tolerant, "PBR_ALBEDO_TOO_DARK");
  ASSERT_EQ(dark_tolerant.size(), 1u) << describe(tolerant.messages);
  EXPECT_EQ(dark_tolerant[0].pointer, "/materials/1/pbrMetallicRoughness/baseColorFactor");
  EXPECT_TRUE(contains(dark_tolerant[0].message, "darker than 0.003 (linear luminance, sRGB 10; the tolerant"))
      << dark_tolerant[0].message;
  const auto dark_strict = issues_with(strict, "PBR_ALBEDO_TOO_DARK");
  ASSERT_EQ(dark_strict.size(), 2u) << describe(strict.messages);
  EXPECT_TRUE(contains(dark_strict[0].message, "darker than 0.012 (linear luminance, sRGB 29; the strict"))
      << dark_strict[0].message;

  EXPECT_TRUE(issues_with(tolerant, "PBR_METAL_F0_TOO_DARK").empty()) << describe(tolerant.messages);
  const auto metal = issues_with(strict, "PBR_METAL_F0_TOO_DARK");
  ASSERT_EQ(metal.size(), 1u);
  EXPECT_TRUE(contains(metal[0].message, "darker than 0.450 (linear, mean of RGB; the strict profile's floor)"))
      << metal[0].message;
}

TEST(LintProfiles, RoughnessZeroIsInformationInTheDefaultAndAWarningWhenStrict) {
  AssetBuilder builder;
  builder.metal_rough(glm::vec4(0.9f, 0.9f, 0.9f, 1.0f), 1.0, 0.0);  // a chrome mirror
  const auto tolerant = issues_with(validate_in_memory(builder.asset()), "PBR_ROUGHNESS_ZERO");
  const auto strict =
      issues_with(validate_in_memory(builder.asset(), builtin_rules(LintProfile::Strict)), "PBR_ROUGHNESS_ZERO");
  ASSERT_EQ(tolerant.size(), 1u);
  ASSERT_EQ(strict.size(), 1u);
  EXPECT_EQ(tolerant[0].severity, Severity::Information);
  EXPECT_EQ(strict[0].severity, Severity::Warning);
  EXPECT_TRUE(contains(tolerant[0].message, "(tolerant profile)")) << tolerant[0].message;
}

TEST(LintProfiles, NamingARuleThatIsOffByDefaultInTheConfigTurnsItOn) {
  AssetBuilder builder;
  builder.metal_rough(glm::vec4(1.0f), 0.0, 0.5);  // pure white: off in tolerant, flagged by strict
  EXPECT_TRUE(issues_with(validate_in_memory(builder.asset()), "PBR_ALBEDO_TOO_BRIGHT").empty());
  for (const std::string config :
       {"override:\n  PBR_ALBEDO_TOO_BRIGHT: warning\n", "only: [PBR_ALBEDO_TOO_BRIGHT]\n"}) {
    test::ScratchDir scratch;
    test::write_text(scratch / "lint.yaml", config);
    RuleSet rules = builtin_rules();
    IssuePolicy policy;
    apply_user_config(scratch / "lint.yaml", rules, policy);
    const auto bright = issues_with(validate_in_memory(builder.asset(), rules), "PBR_ALBEDO_TOO_BRIGHT");
    ASSERT_EQ(bright.size(), 1u) << config;
    EXPECT_TRUE(contains(bright[0].message, "the tolerant profile's ceiling")) << bright[0].message;
  }
}

}  // namespace
}  // namespace gltf_pbr
