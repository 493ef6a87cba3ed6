// `gltf-pbr preview` end to end through its stand-alone driver: outputs, report, exit codes.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "core/files.hpp"

namespace gltf_pbr {
namespace {

int run_preview(const std::string& arguments) {
  const std::string command = std::string(GLTF_PBR_PREVIEW_CLI) + " " + arguments + " > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(PreviewCommand, WritesImagesAndReportAndExitsZero) {
  const fs::path out = fs::temp_directory_path() / "gltf-pbr-preview-command-test";
  fs::remove_all(out);
  const fs::path input = fs::path(GLTF_PBR_SHARED_DIR) / "assets/BoxTextured/specgloss/BoxTextured.gltf";
  ASSERT_EQ(run_preview(input.string() + " -o " + out.string() + " --size 64"), 0);
  for (const char* name : {"before.png", "after.png", "difference.png", "sheet.png", "report.json"})
    EXPECT_TRUE(fs::exists(out / name)) << name;
  const auto text = read_file(out / "report.json");
  ASSERT_TRUE(text);
  const auto report = nlohmann::json::parse(text->begin(), text->end());
  EXPECT_EQ(report["gbuffer"]["after"]["bytes_per_pixel"], 12);
  EXPECT_EQ(report["gbuffer"]["before"]["bytes_per_pixel"], 14);
  EXPECT_TRUE(report["difference"]["delta_e_2000"]["mean"].is_number());
  EXPECT_TRUE(report["difference"]["rms_db"].is_number());
  fs::remove_all(out);
}

TEST(PreviewCommand, BadInputExitsOneAndBadUsageTwo) {
  const fs::path out = fs::temp_directory_path() / "gltf-pbr-preview-command-test-bad";
  EXPECT_EQ(run_preview("/nonexistent/model.gltf -o " + out.string()), 1);
  EXPECT_EQ(run_preview("--no-such-option -o " + out.string()), 2);
  EXPECT_EQ(run_preview("--grid --brdf phong -o " + out.string()), 2);
  EXPECT_EQ(run_preview(""), 2);  // -o is required
  EXPECT_FALSE(fs::exists(out / "report.json"));
  fs::remove_all(out);
}

}  // namespace
}  // namespace gltf_pbr
