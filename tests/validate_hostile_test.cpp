// Hostile inputs: `validate` answers every one with a report, never a crash, a hang or unbounded
// memory (ASan's allocation limit catches the last in the sanitizer build).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "test_support.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

Report validate_bytes(const test::ScratchDir& dir, const std::string& name, const std::string& bytes) {
  const fs::path file = dir / name;
  std::ofstream(file, std::ios::binary) << bytes;
  return validate_file(file, name, builtin_rules(), {}, ValidateOptions{});
}

std::string glb(const std::string& json, const std::string& bin, std::uint32_t claimed_total = 0,
                std::uint32_t claimed_json = 0) {
  auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  std::string padded = json + std::string((4 - json.size() % 4) % 4, ' ');
  std::string body = u32(claimed_json ? claimed_json : static_cast<std::uint32_t>(padded.size())) + "JSON" + padded;
  if (!bin.empty()) body += u32(static_cast<std::uint32_t>(bin.size())) + std::string("BIN\0", 4) + bin;
  return "glTF" + u32(2) + u32(claimed_total ? claimed_total : static_cast<std::uint32_t>(12 + body.size())) + body;
}

TEST(ValidateHostileInput, EveryConstructedAttackGetsAnErrorReportNotACrash) {
  test::ScratchDir dir;
  const std::string asset = R"("asset": {"version": "2.0"})";
  const std::vector<std::pair<std::string, std::string>> attacks{
      {"deep_arrays.gltf", "{" + asset + R"(, "extras": )" + std::string(200000, '[') + std::string(200000, ']') + "}"},
      {"deep_objects.gltf", [&] {
         std::string nested;
         for (int i = 0; i < 100000; ++i) nested += R"({"a":)";
         nested += "0" + std::string(100000, '}');
         return "{" + asset + R"(, "extras": )" + nested + "}";
       }()},
      {"huge_accessor_count.gltf", "{" + asset + R"(, "buffers": [{"byteLength": 4, "uri": "data:application/octet-stream;base64,AAAAAA=="}],
         "bufferViews": [{"buffer": 0, "byteLength": 4}],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4294967295, "type": "MAT4"}]})"},
      {"huge_sparse_count.gltf", "{" + asset + R"(, "buffers": [{"byteLength": 4, "uri": "data:application/octet-stream;base64,AAAAAA=="}],
         "bufferViews": [{"buffer": 0, "byteLength": 4}],
         "accessors": [{"componentType": 5126, "count": 2000000000, "type": "VEC3",
           "sparse": {"count": 2000000000, "indices": {"bufferView": 0, "componentType": 5125},
                      "values": {"bufferView": 0}}}]})"},
      {"huge_buffer_length.gltf", "{" + asset + R"(, "buffers": [{"byteLength": 9007199254740991,
         "uri": "data:application/octet-stream;base64,AAAAAA=="}]})"},
      {"self_parent.gltf", "{" + asset + R"(, "nodes": [{"children": [0]}, {"children": [2]}, {"children": [1]}],
         "scenes": [{"nodes": [0, 1]}], "scene": 0})"},
      {"draco_garbage.gltf", "{" + asset + R"(, "extensionsUsed": ["KHR_draco_mesh_compression"],
         "extensionsRequired": ["KHR_draco_mesh_compression"],
         "buffers": [{"byteLength": 8, "uri": "data:application/octet-stream;base64,RFJBQ08CAv8="}],
         "bufferViews": [{"buffer": 0, "byteLength": 8}],
         "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,1]}],
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0},
           "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}}]}]})"},
      {"glb_total_length_lie.glb", glb("{" + asset + "}", "", 0xFFFFFFF0u)},
      {"glb_json_length_lie.glb", glb("{" + asset + "}", "", 0, 0x7FFFFFFFu)},
      {"truncated.glb", glb("{" + asset + "}", "").substr(0, 17)},
      {"not_json.gltf", std::string("\xEF\xBB\xBF\x00\xFF{[\"", 8)},
  };
  for (const auto& [name, bytes] : attacks) {
    const Report report = validate_bytes(dir, name, bytes);
    EXPECT_GT(report.count(Severity::Error), 0u) << name << ": a hostile input passed validation";
    EXPECT_LE(report.messages.size(), 10000u) << name << ": the report itself blew up";
  }
}

TEST(ValidateHostileInput, AStepThatCannotFinishLeavesAnErrorInTheReportNotAnException) {
  test::ScratchDir dir;
  const fs::path not_a_folder = dir / "heatmaps";
  std::ofstream(not_a_folder) << "a file where the heat-map folder should be";
  ValidateOptions options;
  options.heatmaps_dir = not_a_folder;  // Avocado fails texel rules, so a heat map must be written
  const fs::path avocado = test::assets_dir() / "Avocado/specgloss/Avocado.gltf";
  const Report report = validate_file(avocado, avocado.string(), builtin_rules(), {}, options);
  EXPECT_TRUE(std::any_of(report.messages.begin(), report.messages.end(),
                          [](const Issue& issue) { return issue.code == "IO_ERROR"; }));
}

TEST(ValidateHostileInput, ADocumentTheLoaderRefusesButTheSpecAllowsSaysTheChecksDidNotRun) {
  // A buffer beside the asset's folder: valid glTF (the Khronos validator reads it), but our
  // loader refuses URIs that leave the folder unless allowed.
  test::ScratchDir dir;
  fs::create_directories(dir / "asset");
  const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::ofstream(dir / "triangle.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(positions.data()), static_cast<std::streamsize>(positions.size() * 4));
  const fs::path file = dir / "asset/outside.gltf";
  std::ofstream(file) << R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"../triangle.bin"}],)"
                         R"("bufferViews":[{"buffer":0,"byteLength":36,"target":34962}],)"
                         R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],)"
                         R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})";
  const Report refused = validate_file(file, "outside.gltf", builtin_rules(), {}, ValidateOptions{});
  // The structure step refuses the URI by the one path policy (never opening the file), and the
  // checks that needed the document say they did not run.
  ASSERT_EQ(refused.messages.size(), 2u);
  EXPECT_EQ(refused.messages[0].code, "IO_ERROR");
  EXPECT_EQ(refused.messages[0].pointer, "/buffers/0/uri");
  EXPECT_NE(refused.messages[0].message.find("outside the asset's folder"), std::string::npos)
      << refused.messages[0].message;
  EXPECT_EQ(refused.messages[1].code, "PBR_CHECKS_NOT_RUN");
  EXPECT_EQ(refused.messages[1].pointer, "/buffers/0/uri");
  EXPECT_NE(refused.messages[1].message.find("checks did not run"), std::string::npos) << refused.messages[1].message;
  ValidateOptions allowed;
  allowed.allow_outside_uris = true;
  EXPECT_TRUE(validate_file(file, "outside.gltf", builtin_rules(), {}, allowed).messages.empty());
}

TEST(ValidateHostileInput, FuzzRegressionsGiveReports) {
  const fs::path folder = fs::path(GLTF_PBR_SOURCE_DIR) / "tests/fuzz_regressions";
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() == ".md") continue;
    const Report report = validate_file(entry.path(), entry.path().filename().string(), builtin_rules(), {}, {});
    EXPECT_FALSE(report.mime_type.empty()) << entry.path();
    EXPECT_NO_THROW((void)report_to_json(report).dump()) << entry.path();  // as the fuzz target serialises it
  }
}

}  // namespace
}  // namespace gltf_pbr
