// `gltf-pbr preview` end to end through its stand-alone driver: outputs, report, exit codes.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/files.hpp"
#include "preview/preview.hpp"

namespace gltf_pbr {
namespace {

int run_preview(const std::string& arguments, bool quiet_stderr = true) {
  const std::string command =
      std::string(GLTF_PBR_PREVIEW_CLI) + " " + arguments + (quiet_stderr ? " > /dev/null 2>&1" : " > /dev/null");
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(PreviewCommand, WritesImagesAndReportAndExitsZero) {
  const fs::path out = fs::temp_directory_path() / "gltf-pbr-preview-command-test";
  fs::remove_all(out);
  const fs::path input = fs::path(GLTF_PBR_SHARED_DIR) / "assets/BoxTextured/specgloss/BoxTextured.gltf";
  ASSERT_EQ(run_preview(input.string() + " -o " + out.string() + " --size 64"), 0);
  // The files the CLI checks against the input's before drawing (kPreviewFiles), and the gallery page.
  std::set<std::string> written;
  for (const auto& entry : fs::directory_iterator(out)) written.insert(entry.path().filename().string());
  std::set<std::string> planned{"index.html"};
  for (const char* name : preview::kPreviewFiles) planned.insert(name);
  EXPECT_EQ(written, planned);
  for (const char* name : {"before.png", "after.png", "difference.png", "sheet.png", "report.json"})
    EXPECT_TRUE(planned.contains(name)) << name;
  const auto text = read_file(out / "report.json");
  ASSERT_TRUE(text);
  const auto report = nlohmann::json::parse(text->begin(), text->end());
  EXPECT_EQ(report["gbuffer"]["after"]["bytes_per_pixel"], 12);
  EXPECT_EQ(report["gbuffer"]["before"]["bytes_per_pixel"], 14);
  EXPECT_TRUE(report["difference"]["delta_e_2000"]["mean"].is_number());
  EXPECT_TRUE(report["difference"]["rms_db"].is_number());
  fs::remove_all(out);
}

nlohmann::json report_in(const fs::path& folder) {
  const auto text = read_file(folder / "report.json");
  return text ? nlohmann::json::parse(text->begin(), text->end()) : nlohmann::json();
}

std::set<std::string> codes_of(const nlohmann::json& issues) {
  std::set<std::string> codes;
  for (const auto& issue : issues) codes.insert(issue["code"].get<std::string>());
  return codes;
}

// --lint runs the material rules on the input and its conversion: the legacy material's hint goes
// with the conversion, and only PBR_* issues are kept. Without it they are not run, and say so.
TEST(PreviewCommand, LintPutsTheMaterialIssuesOfBothSidesIntoTheReport) {
  const fs::path out = fs::temp_directory_path() / "gltf-pbr-preview-lint-test";
  fs::remove_all(out);
  const fs::path input = fs::path(GLTF_PBR_SHARED_DIR) / "assets/Avocado/specgloss/Avocado.gltf";
  ASSERT_EQ(run_preview(input.string() + " -o " + (out / "tolerant").string() + " --size 64 --lint"), 0);
  const nlohmann::json tolerant = report_in(out / "tolerant")["material_issues"];
  ASSERT_TRUE(tolerant.is_object()) << tolerant;
  EXPECT_EQ(tolerant["profile"], "tolerant");
  EXPECT_TRUE(codes_of(tolerant["before"]).contains("PBR_LEGACY_SPEC_GLOSS")) << tolerant;
  EXPECT_FALSE(codes_of(tolerant["after"]).contains("PBR_LEGACY_SPEC_GLOSS")) << tolerant;
  for (const char* side : {"before", "after"})
    for (const auto& issue : tolerant[side]) {
      EXPECT_TRUE(issue["code"].get<std::string>().starts_with("PBR_")) << issue;
      EXPECT_TRUE(issue["pointer"].get<std::string>().starts_with("/materials/")) << issue;
    }
  // The strict profile judges harder: at least as many issues on the output.
  ASSERT_EQ(run_preview(input.string() + " -o " + (out / "strict").string() + " --size 64 --lint=strict"), 0);
  const nlohmann::json strict = report_in(out / "strict")["material_issues"];
  EXPECT_EQ(strict["profile"], "strict");
  EXPECT_GE(strict["after"].size(), tolerant["after"].size());
  ASSERT_EQ(run_preview(input.string() + " -o " + (out / "unchecked").string() + " --size 64"), 0);
  const nlohmann::json unchecked = report_in(out / "unchecked");
  ASSERT_TRUE(unchecked.contains("material_issues"));
  EXPECT_TRUE(unchecked["material_issues"].is_null());
  EXPECT_EQ(run_preview("--grid --lint -o " + (out / "grid").string()), 2);
  fs::remove_all(out);
}

// The in-memory conversion takes convert's --metalness-tolerance: BoxTextured's metalness map,
// every value against the default's fewer levels, draws the same before and another after; a
// negative tolerance is bad usage.
TEST(PreviewCommand, DrawsItsConversionWithTheMetalnessToleranceGiven) {
  const fs::path out = fs::temp_directory_path() / "gltf-pbr-preview-command-test-tolerance";
  fs::remove_all(out);
  const std::string input = (fs::path(GLTF_PBR_SHARED_DIR) / "assets/BoxTextured/specgloss/BoxTextured.gltf").string();
  ASSERT_EQ(run_preview(input + " -o " + (out / "every").string() + " --size 128 --metalness-tolerance 0"), 0);
  ASSERT_EQ(run_preview(input + " -o " + (out / "default").string() + " --size 128"), 0);
  EXPECT_EQ(read_file(out / "every" / "before.png"), read_file(out / "default" / "before.png"));
  EXPECT_NE(read_file(out / "every" / "after.png"), read_file(out / "default" / "after.png"));
  EXPECT_EQ(run_preview(input + " -o " + (out / "bad").string() + " --metalness-tolerance -1"), 2);
  EXPECT_FALSE(fs::exists(out / "bad" / "report.json"));
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

TEST(PreviewCommand, AFolderIsDrawnFileByFileIntoOneGalleryAndAFailingFileIsNamed) {
  const fs::path scratch =
      fs::temp_directory_path() / ("gltf-pbr-preview-command-test-folder-" + std::to_string(::getpid()));
  fs::remove_all(scratch);
  const fs::path in = scratch / "in", out = scratch / "out", cache = scratch / "cache";
  fs::create_directories(in / "broken");
  fs::copy(fs::path(GLTF_PBR_SHARED_DIR) / "assets/Box/specgloss", in / "box", fs::copy_options::recursive);
  fs::copy(fs::path(GLTF_PBR_SHARED_DIR) / "assets/Duck/specgloss", in / "duck", fs::copy_options::recursive);
  { std::ofstream(in / "broken" / "Broken.gltf") << "{ not json"; }
  const auto stderr_of = [&](const std::string& arguments, int* exit_code) {
    *exit_code = run_preview(
        in.string() + " -o " + out.string() + " --size 32 -j 2 " + arguments + " 2> " + (scratch / "stderr").string(),
        /*quiet_stderr=*/false);
    const auto text = read_file(scratch / "stderr");
    return text ? std::string(text->begin(), text->end()) : std::string();
  };
  int exit_code = -1;
  std::string said = stderr_of("--cache " + cache.string(), &exit_code);
  EXPECT_EQ(exit_code, 1) << said;  // one file could not be drawn; the others were
  EXPECT_NE(said.find("Broken.gltf"), std::string::npos) << said;
  EXPECT_NE(said.find("2 drawn, 0 from the cache, 1 failed"), std::string::npos) << said;
  std::set<std::string> inputs;
  for (const auto& entry : fs::recursive_directory_iterator(out))
    if (entry.path().filename() == "report.json") {
      const auto text = read_file(entry.path());
      const auto report = nlohmann::json::parse(text->begin(), text->end());
      inputs.insert(fs::path(report["input"].get<std::string>()).filename().string());
      for (const char* image : {"before.png", "after.png", "difference.png"})
        EXPECT_TRUE(fs::exists(entry.path().parent_path() / image)) << entry.path();
      // Each file's folder is its path under the input without the extension, as convert --preview.
      EXPECT_EQ(entry.path().parent_path().filename(), fs::path(report["input"].get<std::string>()).stem());
    }
  EXPECT_EQ(inputs, (std::set<std::string>{"Box.gltf", "Duck.gltf"}));
  const auto page = read_file(out / "index.html");
  ASSERT_TRUE(page);
  const std::string html(page->begin(), page->end());
  EXPECT_NE(html.find("Box.gltf"), std::string::npos);
  EXPECT_NE(html.find("Duck.gltf"), std::string::npos);

  said = stderr_of("--cache " + cache.string(), &exit_code);
  EXPECT_EQ(exit_code, 1) << said;
  EXPECT_NE(said.find("0 drawn, 2 from the cache, 1 failed"), std::string::npos) << said;

  // Duck broken after it was drawn: its earlier previews go, so the page no longer lists it.
  { std::ofstream(in / "duck" / "Duck.gltf") << "{ not json"; }
  said = stderr_of("", &exit_code);
  EXPECT_EQ(exit_code, 1) << said;
  EXPECT_NE(said.find("its earlier previews removed"), std::string::npos) << said;
  for (const auto& entry : fs::recursive_directory_iterator(out))
    EXPECT_NE(entry.path().parent_path().filename(), "Duck") << entry.path();
  const auto rewritten = read_file(out / "index.html");
  ASSERT_TRUE(rewritten);
  EXPECT_EQ(std::string(rewritten->begin(), rewritten->end()).find("Duck.gltf"), std::string::npos);
  fs::remove_all(scratch);
}

}  // namespace
}  // namespace gltf_pbr
