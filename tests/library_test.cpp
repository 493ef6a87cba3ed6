// The C++ library through its public header only, linked as a consumer links it (libgltf_pbr.so):
// batches, previews, validation steps and option checks on real assets from ../shared.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <gltf_pbr/gltf_pbr.hpp>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

const fs::path kShared = GLTF_PBR_SHARED_DIR;
const fs::path kDuck = kShared / "assets/Duck/specgloss/Duck.gltf";
const fs::path kBox = kShared / "assets/Box/specgloss/Box.gltf";

// A folder of this test process's own (the plain and sanitizer builds may run at once), removed
// when the test ends.
struct TempFolder {
  explicit TempFolder(const std::string& name)
      : path(fs::temp_directory_path() / ("gltf_pbr_library_test_" + std::to_string(::getpid()) + "_" + name)) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
  fs::path path;
};

TEST(Library, ConvertFilesReportsAFailingFileAndConvertsTheRest) {
  const TempFolder folder("batch");
  const fs::path& out = folder.path;
  const std::vector<gltf_pbr::ConvertJob> jobs{{kDuck, out / "Duck.glb", {}},
                                               {out / "missing.gltf", out / "missing_out.gltf", {}},
                                               {kBox, out / "Box.gltf", {}}};
  std::atomic<int> done{0};
  const auto results = gltf_pbr::convert_files(jobs, {}, 2, [&](const gltf_pbr::FileConversion&) { ++done; });
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(done.load(), 3);
  EXPECT_EQ(results[0].status, gltf_pbr::FileStatus::Converted);
  EXPECT_EQ(results[0].input, kDuck);
  EXPECT_EQ(results[0].materials, 1u);
  EXPECT_GT(results[0].texels, 0);
  EXPECT_NE(results[0].report_json.find("\"outcome\": \"metalness\""), std::string::npos);
  EXPECT_EQ(results[1].status, gltf_pbr::FileStatus::Failed);
  ASSERT_TRUE(results[1].error.has_value());
  EXPECT_EQ(results[1].error->file, (out / "missing.gltf").string());
  EXPECT_FALSE(fs::exists(out / "missing_out.gltf"));
  EXPECT_EQ(results[2].status, gltf_pbr::FileStatus::Converted);
  EXPECT_GT(fs::file_size(out / "Duck.glb"), 0u);
  EXPECT_GT(fs::file_size(out / "Box.gltf"), 0u);
}

TEST(Library, ConvertFilesRefusesTwoJobsWritingOneFile) {
  // They would race, and the loser's images would stay beside the winner's output.
  const TempFolder folder("same_output");
  const std::vector<gltf_pbr::ConvertJob> jobs{{kDuck, folder.path / "same.gltf", {}},
                                               {kBox, folder.path / "." / "same.gltf", {}}};
  EXPECT_THROW(gltf_pbr::convert_files(jobs), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(folder.path)) << "refused before anything is written";
}

TEST(Library, ConvertFileThrowsInputErrorNamingThePointer) {
  const TempFolder folder("pointer");
  const fs::path& out = folder.path;
  std::ofstream(out / "broken.gltf") << R"({"asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"],
    "materials": [{"extensions": {"KHR_materials_pbrSpecularGlossiness": {"diffuseTexture": {"index": 5}}}}]})";
  try {
    gltf_pbr::convert_file({out / "broken.gltf", out / "out.gltf"});
    FAIL() << "converted a material whose texture does not exist";
  } catch (const gltf_pbr::InputError& e) {
    EXPECT_EQ(e.file, (out / "broken.gltf").string());
    EXPECT_EQ(e.pointer.rfind("/materials/0", 0), 0u) << e.pointer;
    EXPECT_FALSE(e.reason.empty());
  }
  EXPECT_FALSE(fs::exists(out / "out.gltf"));
}

TEST(Library, ValidateFileRunsOnlyTheStepsAskedFor) {
  gltf_pbr::ValidateFileOptions structure_only;
  structure_only.steps = {gltf_pbr::ValidationStep::Structure};
  const gltf_pbr::FileValidation all = gltf_pbr::validate_file(kDuck);
  const gltf_pbr::FileValidation structure = gltf_pbr::validate_file(kDuck, structure_only);
  EXPECT_NE(all.report_json.find("PBR_LEGACY_SPEC_GLOSS"), std::string::npos);
  EXPECT_EQ(structure.report_json.find("PBR_"), std::string::npos);
  EXPECT_EQ(structure.report_json.find("MESH_"), std::string::npos);
  EXPECT_NE(structure.report_json.find("\"validatorVersion\": \"gltf-pbr " + gltf_pbr::version() + "\""),
            std::string::npos);
  EXPECT_GT(all.warnings, structure.warnings);
}

TEST(Library, PreviewFileWritesItsImagesAndReport) {
  const TempFolder folder("preview");
  const fs::path& out = folder.path;
  gltf_pbr::PreviewFileOptions options;
  options.width = options.height = 64;
  const gltf_pbr::FilePreview preview = gltf_pbr::preview_file(kDuck, out, options);
  ASSERT_EQ(preview.images.size(), 4u);
  for (const fs::path& image : preview.images) {
    std::ifstream file(image, std::ios::binary);
    char signature[4] = {};
    file.read(signature, 4);
    EXPECT_EQ(std::string(signature + 1, 3), "PNG") << image;
  }
  std::stringstream written;
  written << std::ifstream(out / "report.json").rdbuf();
  EXPECT_EQ(written.str(), preview.report_json + "\n");
  // Duck's conversion is visibly paler (issue 12): a preview of it must measure a difference.
  EXPECT_GT(preview.delta_e_mean, 0.0);
  EXPECT_GE(preview.delta_e_p95, preview.delta_e_mean);
  EXPECT_GT(preview.flip_mean, 0.0);
  EXPECT_LE(preview.flip_mean, 1.0);
}

TEST(Library, OptionsOutOfRangeAreRefusedByName) {
  gltf_pbr::ConvertFileOptions convert;
  convert.png_compression = 10;
  try {
    gltf_pbr::convert_file({kDuck, TempFolder("range").path / "out.gltf"}, convert);
    FAIL() << "accepted png_compression 10";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "png_compression must be 0-9, got 10");
  }
  gltf_pbr::PreviewFileOptions preview;
  preview.width = 0;
  EXPECT_THROW(gltf_pbr::preview_file(kDuck, TempFolder("range_preview").path, preview), std::invalid_argument);
}

TEST(Library, NamesRoundTripAndUnknownNamesAreRefused) {
  for (auto target : {gltf_pbr::Target::Metalness, gltf_pbr::Target::Specular})
    EXPECT_EQ(gltf_pbr::target_from_name(gltf_pbr::target_name(target)), target);
  for (auto effort : {gltf_pbr::SolverEffort::Fast, gltf_pbr::SolverEffort::Balanced, gltf_pbr::SolverEffort::Exact,
                      gltf_pbr::SolverEffort::Reference})
    EXPECT_EQ(gltf_pbr::solver_effort_from_name(gltf_pbr::solver_effort_name(effort)), effort);
  for (auto step : {gltf_pbr::ValidationStep::Structure, gltf_pbr::ValidationStep::Materials,
                    gltf_pbr::ValidationStep::Textures, gltf_pbr::ValidationStep::Meshes})
    EXPECT_EQ(gltf_pbr::validation_step_from_name(gltf_pbr::validation_step_name(step)), step);
  EXPECT_FALSE(gltf_pbr::target_from_name("Metalness").has_value());
  EXPECT_FALSE(gltf_pbr::solver_effort_from_name("").has_value());
}

}  // namespace
