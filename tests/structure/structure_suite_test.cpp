// Runs every case of the Khronos validator suite (../shared/validator-suite/manifest.json) through
// validate_structure and compares with the expected reports, in the README's tiers:
//   tier 1: the ordered list of (code, pointer-or-offset, severity) is equal;
//   tier 2: the same lists, ignoring order;
//   messages: tier 1 and every message text equal.
// It prints the shares and each tier-1 mismatch, and fails below the thresholds we have reached.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "tests/structure/coverage.hpp"
#include "validators/structure/structure.hpp"

namespace gltf_pbr {
namespace {

// Raised as agreement improves: a drop below them is a regression.
constexpr double kMinTier1Agreement = 1.0;
constexpr double kMinTier2Agreement = 1.0;
constexpr double kMinMessageAgreement = 1.0;
constexpr double kMinInfoAgreement = 1.0;  // info equal to the reference's (tier 3 without messages)

const std::filesystem::path kSuiteDir = std::filesystem::path(GLTF_PBR_SHARED_DIR) / "validator-suite";

struct Entry {
  std::string code, location, message;
  int severity = 0;
  bool operator<(const Entry& other) const {
    return std::tie(code, location, severity) < std::tie(other.code, other.location, other.severity);
  }
  bool same_key(const Entry& other) const {
    return code == other.code && location == other.location && severity == other.severity;
  }
};

std::vector<Entry> expected_entries(const nlohmann::json& report) {
  std::vector<Entry> entries;
  for (const auto& message : report["issues"]["messages"]) {
    Entry entry;
    entry.code = message["code"];
    entry.location = message.contains("offset") ? "@" + std::to_string(message["offset"].get<std::uint64_t>())
                                                : message.value("pointer", "");
    entry.message = message["message"];
    entry.severity = message["severity"];
    entries.push_back(entry);
  }
  return entries;
}

std::vector<Entry> actual_entries(const Report& report) {
  std::vector<Entry> entries;
  for (const Issue& issue : report.messages)
    entries.push_back({issue.code, issue.offset ? "@" + std::to_string(*issue.offset) : issue.pointer, issue.message,
                       static_cast<int>(issue.severity)});
  return entries;
}

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

std::string show(const std::vector<Entry>& entries) {
  std::string text;
  for (const Entry& entry : entries)
    text += "      " + entry.code + " " + std::to_string(entry.severity) + " " + entry.location + " | " +
            entry.message + "\n";
  return text;
}

TEST(StructureSuite, AgreesWithKhronosExpectedReports) {
  std::ifstream manifest_stream(kSuiteDir / "manifest.json");
  ASSERT_TRUE(manifest_stream) << "missing " << (kSuiteDir / "manifest.json");
  const nlohmann::json manifest = nlohmann::json::parse(manifest_stream);
  // The reference runs from the suite directory with relative paths (README "Layout").
  const auto previous_dir = std::filesystem::current_path();
  std::filesystem::current_path(kSuiteDir);
  std::size_t cases = 0, tier1 = 0, tier2 = 0, messages = 0, infos = 0;
  std::string mismatches, message_mismatches, info_mismatches;
  const char* filter = std::getenv("STRUCTURE_SUITE_FILTER");
  for (const auto& entry : manifest["cases"]) {
    const std::string input = entry["input"];
    if (filter && input.find(filter) == std::string::npos) continue;
    ++cases;
    std::ifstream report_stream(entry["report"].get<std::string>());
    const nlohmann::json expected_report = nlohmann::json::parse(report_stream);
    Report report;
    report.uri = input;
    validate_structure(input, read_bytes(input), builtin_rules(), StructureOptions{}, report);
    const auto expected = expected_entries(expected_report);
    for (const Entry& issue : expected) coverage::record_suite_code(issue.code);
    const auto actual = actual_entries(report);
    const bool ordered = std::equal(expected.begin(), expected.end(), actual.begin(), actual.end(),
                                    [](const Entry& a, const Entry& b) { return a.same_key(b); });
    auto sorted_expected = expected, sorted_actual = actual;
    std::sort(sorted_expected.begin(), sorted_expected.end());
    std::sort(sorted_actual.begin(), sorted_actual.end());
    const bool unordered =
        std::equal(sorted_expected.begin(), sorted_expected.end(), sorted_actual.begin(), sorted_actual.end(),
                   [](const Entry& a, const Entry& b) { return a.same_key(b); });
    tier1 += ordered;
    tier2 += unordered;
    const bool texts = ordered && std::equal(expected.begin(), expected.end(), actual.begin(),
                                             [](const Entry& a, const Entry& b) { return a.message == b.message; });
    messages += texts;
    const nlohmann::json expected_info = expected_report.value("info", nlohmann::json());
    const nlohmann::json actual_info = nlohmann::json::parse(report.info.dump());
    if (expected_info == actual_info)
      ++infos;
    else
      info_mismatches +=
          "  " + input + "\n    expected: " + expected_info.dump() + "\n    actual:   " + actual_info.dump() + "\n";
    if (!ordered)
      mismatches += "  " + input + (unordered ? " (order only)" : "") + "\n    expected:\n" + show(expected) +
                    "    actual:\n" + show(actual);
    else if (!texts)
      message_mismatches += "  " + input + "\n    expected:\n" + show(expected) + "    actual:\n" + show(actual);
  }
  std::filesystem::current_path(previous_dir);
  ASSERT_GT(cases, 0u);
  const double share1 = double(tier1) / double(cases), share2 = double(tier2) / double(cases),
               share_messages = double(messages) / double(cases);
  std::cout << "Tier-1 mismatches:\n" << mismatches;
  if (std::getenv("STRUCTURE_SUITE_MESSAGES")) std::cout << "Message mismatches:\n" << message_mismatches;
  if (std::getenv("STRUCTURE_SUITE_INFO")) std::cout << "Info mismatches:\n" << info_mismatches;
  const double share_info = double(infos) / double(cases);
  std::cout << "structure suite: " << cases << " cases; tier 1 (ordered code, location, severity) " << tier1 << " ("
            << share1 * 100 << "%); tier 2 (unordered) " << tier2 << " (" << share2 * 100 << "%); messages " << messages
            << " (" << share_messages * 100 << "%); info " << infos << " (" << share_info * 100 << "%)\n";
  EXPECT_GE(share1, kMinTier1Agreement);
  EXPECT_GE(share2, kMinTier2Agreement);
  EXPECT_GE(share_messages, kMinMessageAgreement);
  EXPECT_GE(share_info, kMinInfoAgreement);
}

}  // namespace
}  // namespace gltf_pbr
