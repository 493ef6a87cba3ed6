// One front end: the steps of one `validate` read a file's resources through one FileResources
// (core/resources.hpp), so each external file is opened once and each Draco mesh decoded once,
// whichever steps ask for them.
#include "api/files.hpp"
#include "core/resources.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "rules/rule_set.hpp"
#include "test_support.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

using test::assets_dir;
using test::ScratchDir;

// The distinct bufferViews that a file's KHR_draco_mesh_compression primitives decode from.
std::set<int> draco_views(const fs::path& gltf) {
  const nlohmann::json document = nlohmann::json::parse(test::read_text(gltf));
  std::set<int> views;
  for (const auto& mesh : document.at("meshes"))
    for (const auto& primitive : mesh.at("primitives"))
      if (primitive.contains("extensions") && primitive["extensions"].contains("KHR_draco_mesh_compression"))
        views.insert(primitive["extensions"]["KHR_draco_mesh_compression"].at("bufferView").get<int>());
  return views;
}

// Each step alone decodes every mesh; together they still decode each once.
TEST(OneFrontEnd, ValidateDecodesEachDracoMeshOnceForTheStructureAndMeshSteps) {
  const fs::path gltf = assets_dir() / "2CylinderEngine/metalrough-draco/2CylinderEngine.gltf";
  const long meshes = static_cast<long>(draco_views(gltf).size());
  ASSERT_GT(meshes, 1);
  auto decoded_by = [&](std::set<ValidationStep> steps) {
    ValidateOptions options;
    options.steps = std::move(steps);
    options.self_intersections = false;
    const long before = work_counters().meshes_decoded;
    const Report report = validate_file(gltf, "2CylinderEngine.gltf", builtin_rules(), {}, options);
    for (const Issue& issue : report.messages)
      EXPECT_TRUE(issue.code != "MESH_PRIMITIVE_UNREADABLE" && issue.code != "DRACO_DECODE_FAILED") << issue.message;
    return work_counters().meshes_decoded - before;
  };
  EXPECT_EQ(decoded_by({ValidationStep::Structure}), meshes);
  EXPECT_EQ(decoded_by({ValidationStep::Meshes}), meshes);
  EXPECT_EQ(decoded_by({ValidationStep::Structure, ValidationStep::Meshes}), meshes);
}

TEST(OneFrontEnd, ValidateOpensEachExternalFileOnceAndDecodesEachImageOnce) {
  const fs::path gltf = assets_dir() / "BoxTextured/specgloss/BoxTextured.gltf";
  const long opened = work_counters().files_opened, decoded = work_counters().images_decoded;
  const Report report = validate_file(gltf, "BoxTextured.gltf", builtin_rules(), {}, ValidateOptions{});
  EXPECT_EQ(work_counters().files_opened - opened, 2);  // BoxTextured0.bin and CesiumLogoFlat.png
  EXPECT_EQ(work_counters().images_decoded - decoded, 1);
  EXPECT_FALSE(report.info.is_null());
}

// The structure step's JSON tree is the loader's: validate reads the file and its JSON text once
// whichever steps run, and the document library's own parse is its only other one.
TEST(OneFrontEnd, ValidateReadsTheFileAndItsJsonOnceWhicheverStepsRun) {
  for (const char* model : {"BoxTextured/specgloss/BoxTextured.gltf", "BoxTextured/metalrough-glb/BoxTextured.glb"}) {
    const fs::path file = assets_dir() / model;
    auto reads_by = [&](std::set<ValidationStep> steps) {
      ValidateOptions options;
      options.steps = std::move(steps);
      const long before = work_counters().json_texts_read, loaded = work_counters().assets_loaded;
      const long documents = work_counters().documents_read;
      const Report report = validate_file(file, file.filename().string(), builtin_rules(), {}, options);
      EXPECT_EQ(work_counters().documents_read - documents, 1) << model;
      for (const Issue& issue : report.messages) EXPECT_NE(issue.code, "PBR_CHECKS_NOT_RUN") << issue.message;
      const bool needs_document = !options.steps.contains(ValidationStep::Structure) || options.steps.size() > 1;
      EXPECT_EQ(work_counters().assets_loaded - loaded, needs_document ? 1 : 0) << model;
      return work_counters().json_texts_read - before;
    };
    EXPECT_EQ(reads_by({ValidationStep::Structure}), 1) << model;
    EXPECT_EQ(reads_by({ValidationStep::Materials, ValidationStep::Textures}), 1) << model;
    EXPECT_EQ(reads_by({ValidationStep::Structure, ValidationStep::Materials, ValidationStep::Textures,
                        ValidationStep::Meshes}),
              1)
        << model;
  }
}

// convert reads the file once and parses its JSON once with our reader, whether it converts the
// file or copies it unchanged: the scan for values that loading would drop keeps its tree for the
// loader, and the copy takes the bytes the load read. A second parse or read would count here.
TEST(OneFrontEnd, ConvertReadsTheFileAndItsJsonOnce) {
  ScratchDir scratch;
  for (const auto& [model, status] :
       {std::pair{"BoxTextured/specgloss/BoxTextured.gltf", FileStatus::Converted},
        std::pair{"BoxTextured/metalrough-glb/BoxTextured.glb", FileStatus::Copied}}) {
    const fs::path input = assets_dir() / model;
    const long documents = work_counters().documents_read, texts = work_counters().json_texts_read;
    const FileResult done = convert_or_throw({input, scratch / fs::path(model).parent_path() / input.filename()}, {});
    EXPECT_EQ(done.status, status) << model;
    EXPECT_EQ(work_counters().documents_read - documents, 1) << model;
    EXPECT_EQ(work_counters().json_texts_read - texts, 1) << model;
  }
}

// A .gltf copied unchanged to another folder takes its buffer and image along as the load mapped
// them: each external file is opened once, and the copies hold the same bytes.
TEST(OneFrontEnd, ACopiedGltfTakesItsResourcesFromTheLoadersMappings) {
  ScratchDir scratch;
  const fs::path input = assets_dir() / "BoxTextured/metalrough/BoxTextured.gltf";
  const long opened = work_counters().files_opened;
  const FileResult done = convert_or_throw({input, scratch / "copy" / "BoxTextured.gltf"}, {});
  EXPECT_EQ(done.status, FileStatus::Copied);
  EXPECT_EQ(work_counters().files_opened - opened, 2);  // BoxTextured0.bin, CesiumLogoFlat.png
  for (const char* name : {"BoxTextured.gltf", "BoxTextured0.bin", "CesiumLogoFlat.png"})
    EXPECT_EQ(read_file(scratch / "copy" / name), read_file(input.parent_path() / name)) << name;
}

// preview --lint reads the textures the preview decoded: the material rules on both sides decode
// none of them again (Avocado: the conversion reads two legacy maps and bakes two).
TEST(OneFrontEnd, PreviewLintDecodesNoImageThePreviewAlreadyHolds) {
  ScratchDir scratch;
  const fs::path input = assets_dir() / "Avocado/specgloss/Avocado.gltf";
  preview::PreviewOptions options;
  options.width = options.height = 32;
  auto decodes = [&](std::optional<LintProfile> lint, const std::string& folder) {
    const long before = work_counters().images_decoded;
    const DrawnPreview drawn = preview_one(input, scratch / folder, options, false, lint);
    EXPECT_EQ(drawn.report["material_issues"].is_null(), !lint.has_value());
    return work_counters().images_decoded - before;
  };
  const long without = decodes(std::nullopt, "plain");
  EXPECT_GT(without, 0);
  EXPECT_EQ(decodes(LintProfile::Tolerant, "lint"), without);
}

// One code for one finding: a non-power-of-two image is IMAGE_NPOT_DIMENSIONS with the same
// message and pointer whether the structure step or, without it, the texture step reads its size.
TEST(OneFrontEnd, NonPowerOfTwoImageIsOneIssueWhicheverStepsRun) {
  const fs::path gltf = assets_dir() / "BoxTexturedNonPowerOfTwo/specgloss/BoxTexturedNonPowerOfTwo.gltf";
  auto npot_issues = [&](std::set<ValidationStep> steps) {
    ValidateOptions options;
    options.steps = std::move(steps);
    std::vector<std::pair<std::string, std::string>> found;
    for (const Issue& issue : validate_file(gltf, "BoxTexturedNonPowerOfTwo.gltf", builtin_rules(), {}, options).messages)
      if (issue.code == "IMAGE_NPOT_DIMENSIONS") found.emplace_back(issue.pointer, issue.message);
    return found;
  };
  const auto all_steps = npot_issues({ValidationStep::Structure, ValidationStep::Materials, ValidationStep::Textures,
                                      ValidationStep::Meshes});
  ASSERT_EQ(all_steps.size(), 1u);
  EXPECT_EQ(all_steps[0].first, "/images/0");
  EXPECT_EQ(all_steps[0].second, "Image has non-power-of-two dimensions: 211x211.");
  EXPECT_EQ(npot_issues({ValidationStep::Textures}), all_steps);
  EXPECT_EQ(npot_issues({ValidationStep::Structure}), all_steps);
  EXPECT_TRUE(npot_issues({ValidationStep::Materials, ValidationStep::Meshes}).empty());
}

TEST(OneFrontEnd, AResourceNamedTwiceIsOneFileOpenedOnce) {
  ScratchDir scratch;
  test::write_text(scratch / "data.bin", "0123");
  FileResources resources(scratch.path(), false);
  const long opened = work_counters().files_opened;
  const FileResources::External& first = resources.external("data.bin");
  const FileResources::External& again = resources.external("data.bin");
  ASSERT_TRUE(first.file);
  EXPECT_EQ(first.file, again.file);
  EXPECT_EQ(std::string(first.file->bytes().begin(), first.file->bytes().end()), "0123");
  EXPECT_EQ(work_counters().files_opened - opened, 1);
}

TEST(OneFrontEnd, ARefusedUriIsNeverOpened) {
  ScratchDir scratch;
  fs::create_directories(scratch / "asset");
  test::write_text(scratch / "outside.bin", "secret");
  FileResources resources(scratch / "asset", false);
  const long opened = work_counters().files_opened;
  const FileResources::External& outside = resources.external("../outside.bin");
  EXPECT_EQ(outside.resolved.status, UriStatus::Refused);
  EXPECT_FALSE(outside.file);
  EXPECT_EQ(resources.external("missing.bin").resolved.status, UriStatus::NotFound);
  EXPECT_EQ(work_counters().files_opened, opened);
}

TEST(OneFrontEnd, DracoDataThatDoesNotDecodeIsRememberedWithItsReason) {
  FileResources resources(".", false, /*keep_draco_meshes=*/true);
  const std::vector<std::uint8_t> junk{'D', 'R', 'A', 'C', 'O', 0, 0, 0, 1, 2, 3};
  const FileResources::DracoMesh first = resources.draco_mesh(junk);
  EXPECT_FALSE(first.mesh);
  EXPECT_FALSE(first.problem.empty());
  EXPECT_EQ(resources.draco_mesh(junk).problem, first.problem);
}

}  // namespace
}  // namespace gltf_pbr
