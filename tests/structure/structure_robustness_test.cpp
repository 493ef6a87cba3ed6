// Hostile and malformed inputs: the structure validator reports them and never crashes, hangs or
// allocates what the bytes cannot back.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/structure/coverage.hpp"
#include "validators/structure/structure.hpp"

namespace gltf_pbr {
namespace {

using coverage::validate_text;

bool has(const Report& report, const std::string& code, const std::string& pointer) {
  for (const Issue& issue : report.messages)
    if (issue.code == code && issue.pointer == pointer) return true;
  return false;
}

TEST(StructureRobustness, HugeAccessorCountWithoutBufferViewIsNotAllocated) {
  const Report report = validate_text(
      R"({"asset":{"version":"2.0"},"accessors":[{"componentType":5126,"count":9007199254740991,"type":"MAT4",)"
      R"("min":[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0],"max":[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]}]})");
  EXPECT_TRUE(has(report, "UNUSED_OBJECT", "/accessors/0"));
}

TEST(StructureRobustness, HugeCountInSmallBufferViewIsTooLong) {
  const Report report = validate_text(
      R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"data:application/octet-stream;base64,AAAAAA=="}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":4}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":4611686018427387903,"type":"VEC4"}]})");
  EXPECT_TRUE(has(report, "ACCESSOR_TOO_LONG", "/accessors/0"));
}

TEST(StructureRobustness, DeepNestingIsInvalidJsonNotAStackOverflow) {
  std::string deep(100000, '[');
  deep += std::string(100000, ']');
  const Report report = validate_text(R"({"asset":{"version":"2.0"},"extras":)" + deep + "}");
  EXPECT_TRUE(has(report, "INVALID_JSON", ""));
}

TEST(StructureRobustness, NumbersBeyondDoubleRangeAreInfinite) {
  const Report report = validate_text(R"({"asset":{"version":"2.0"},"nodes":[{"translation":[1e309,0,0]}]})");
  EXPECT_TRUE(has(report, "VALUE_NOT_IN_RANGE", "/nodes/0/translation/0"));
  EXPECT_EQ(report.messages[0].message, "Value Infinity is out of range.");
}

TEST(StructureRobustness, TruncatedGlbHeaderIsReportedAtItsEnd) {
  const std::vector<std::uint8_t> bytes = {'g', 'l', 'T', 'F', 2, 0};
  const Report report = coverage::validate_and_record("x.glb", bytes);
  ASSERT_EQ(report.messages.size(), 1u);
  EXPECT_EQ(report.messages[0].code, "GLB_UNEXPECTED_END_OF_HEADER");
  EXPECT_EQ(report.messages[0].offset, 6u);
}

TEST(StructureRobustness, GlbChunkLengthBeyondFileStopsAtTheEnd) {
  const std::vector<std::uint8_t> bytes = {'g',  'l',  'T', 'F', 2,   0,   0,   0,   28,  0,   0,   0,   0xFF, 0xFF,
                                           0xFF, 0xFF, 'J', 'S', 'O', 'N', '{', '}', ' ', ' ', ' ', ' ', ' ',  ' '};
  const Report report = coverage::validate_and_record("x.glb", bytes);
  ASSERT_FALSE(report.messages.empty());
  EXPECT_EQ(report.messages.back().code, "GLB_UNEXPECTED_END_OF_CHUNK_DATA");
}

TEST(StructureRobustness, UndecodableDracoBufferIsAnErrorAtTheExtension) {
  const Report report = validate_text(
      R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],)"
      R"("extensionsRequired":["KHR_draco_mesh_compression"],)"
      R"("buffers":[{"byteLength":4,"uri":"data:application/octet-stream;base64,AAAAAA=="}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":4}],)"
      R"("accessors":[{"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,1]}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"extensions":{"KHR_draco_mesh_compression":)"
      R"({"bufferView":0,"attributes":{"POSITION":0}}}}]}]})");
  EXPECT_TRUE(has(report, "DRACO_DECODE_FAILED", "/meshes/0/primitives/0/extensions/KHR_draco_mesh_compression"));
}

TEST(StructureRobustness, EverySeverityComesFromTheCatalogue) {
  const Rule& rule = builtin_rules().at("UNUSED_OBJECT");
  const Report report = validate_text(R"({"asset":{"version":"2.0"},"materials":[{}]})");
  ASSERT_EQ(report.messages.size(), 1u);
  EXPECT_EQ(report.messages[0].severity, rule.severity);
  EXPECT_EQ(report.messages[0].message, "This object may be unused.");
}

}  // namespace
}  // namespace gltf_pbr

namespace gltf_pbr {
namespace {

// Every suite input, mutated deterministically (byte flips, truncations, digit runs spliced into
// numbers): the validator must return, whatever the bytes. Run it under the sanitizer build to
// catch undefined behaviour as well as crashes.
TEST(StructureRobustness, MutatedSuiteInputsNeverCrash) {
  const std::filesystem::path suite = std::filesystem::path(GLTF_PBR_SHARED_DIR) / "validator-suite";
  std::ifstream manifest_stream(suite / "manifest.json");
  ASSERT_TRUE(manifest_stream);
  const nlohmann::json manifest = nlohmann::json::parse(manifest_stream);
  const auto previous_dir = std::filesystem::current_path();
  std::filesystem::current_path(suite);
  std::uint32_t state = 12345;
  auto next = [&] { return state = state * 1664525u + 1013904223u; };
  std::size_t runs = 0;
  for (const auto& entry : manifest["cases"]) {
    const std::string input = entry["input"];
    std::ifstream stream(input, std::ios::binary);
    const std::vector<std::uint8_t> original{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
    if (original.empty()) continue;
    for (int round = 0; round < 12; ++round) {
      std::vector<std::uint8_t> bytes = original;
      switch (round % 4) {
        case 0:
          for (int flips = 0; flips < 4; ++flips) bytes[next() % bytes.size()] ^= static_cast<std::uint8_t>(next());
          break;
        case 1:
          bytes.resize(next() % bytes.size());
          break;
        case 2: {
          const std::size_t at = next() % bytes.size();
          const std::string digits = "99999999999999999999";
          bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(at), digits.begin(), digits.end());
          break;
        }
        default:
          for (std::size_t i = 0; i < bytes.size(); ++i)
            if (bytes[i] >= '1' && bytes[i] <= '9' && next() % 3 == 0) bytes[i] = '9';
          break;
      }
      Report report;
      validate_structure(input, bytes, builtin_rules(), StructureOptions{}, report);
      ++runs;
    }
  }
  std::filesystem::current_path(previous_dir);
  EXPECT_GT(runs, 1000u);
}

}  // namespace
}  // namespace gltf_pbr
