// Saving: container round trips keep every byte that matters, and a failed save leaves nothing.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "test_support.hpp"

namespace gltf_pbr {
namespace {

using test::assets_dir;
using test::ScratchDir;

std::vector<std::uint8_t> accessor_bytes(const tinygltf::Model& model, size_t accessor) {
  const auto& view = model.bufferViews.at(static_cast<size_t>(model.accessors.at(accessor).bufferView));
  const auto& data = model.buffers.at(static_cast<size_t>(view.buffer)).data;
  return {data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset),
          data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset + view.byteLength)};
}

// Materials as the document defines them: tinygltf's deprecated `values`/`additionalValues` maps
// are derived on parse and differ with the writer's choice of defaults, not with the content.
std::vector<tinygltf::Material> materials(const tinygltf::Model& model) {
  std::vector<tinygltf::Material> out = model.materials;
  for (auto& m : out) m.values.clear(), m.additionalValues.clear();
  return out;
}

void expect_same_content(const Asset& a, const Asset& b) {
  ASSERT_EQ(a.model.accessors.size(), b.model.accessors.size());
  for (size_t i = 0; i < a.model.accessors.size(); ++i)
    EXPECT_EQ(accessor_bytes(a.model, i), accessor_bytes(b.model, i)) << "accessor " << i;
  ASSERT_EQ(a.model.images.size(), b.model.images.size());
  for (size_t i = 0; i < a.model.images.size(); ++i) {
    const auto x = encoded_image_bytes(a, static_cast<int>(i)), y = encoded_image_bytes(b, static_cast<int>(i));
    EXPECT_TRUE(std::equal(x.begin(), x.end(), y.begin(), y.end())) << "image " << i;
  }
  EXPECT_EQ(materials(a.model), materials(b.model));
  EXPECT_EQ(a.model.meshes, b.model.meshes);
  EXPECT_EQ(a.model.nodes, b.model.nodes);
  EXPECT_EQ(a.model.extensionsUsed, b.model.extensionsUsed);
}

// dump(2)'s text with each array that holds only numbers joined onto one line: a reference
// written against the text rather than the tree, so it shares nothing with the writer.
std::string text_with_numbers_inline(const std::string& text) {
  static const std::regex numbers_array(R"(\[\n\s*(-?[0-9][-+.eE0-9]*(?:,\n\s*-?[0-9][-+.eE0-9]*)*)\n\s*\])");
  static const std::regex separator(R"(,\n\s*)");
  std::string out;
  auto rest = text.cbegin();
  for (std::sregex_iterator it(text.begin(), text.end(), numbers_array), end; it != end; ++it) {
    out.append(rest, (*it)[0].first);
    out += "[" + std::regex_replace((*it)[1].str(), separator, ", ") + "]";
    rest = (*it)[0].second;
  }
  return out.append(rest, text.cend());
}

TEST(SaveRoundTrip, GltfToGlbToGltfKeepsAccessorAndImageBytes) {
  ScratchDir scratch;
  const fs::path input = assets_dir() / "Duck" / "specgloss" / "Duck.gltf";
  Asset original = load_asset(input);
  save_asset(original, scratch / "glb" / "Duck.glb");
  Asset glb = load_asset(scratch / "glb" / "Duck.glb");
  EXPECT_TRUE(glb.binary);
  EXPECT_EQ(glb.model.buffers.size(), 1u);
  for (const auto& image : glb.model.images) EXPECT_GE(image.bufferView, 0) << "a GLB stands alone";
  save_asset(glb, scratch / "gltf" / "Duck.gltf");
  const Asset back = load_asset(scratch / "gltf" / "Duck.gltf");
  expect_same_content(load_asset(input), glb);
  expect_same_content(glb, back);
}

TEST(SaveRoundTrip, UntouchedGltfSavedElsewhereKeepsItsResourceFilesByteForByte) {
  ScratchDir scratch;
  const fs::path folder = assets_dir() / "BoxTextured" / "specgloss";
  Asset asset = load_asset(folder / "BoxTextured.gltf");
  save_asset(asset, scratch / "BoxTextured.gltf");
  EXPECT_EQ(read_file(scratch / "BoxTextured0.bin"), read_file(folder / "BoxTextured0.bin"));
  EXPECT_EQ(read_file(scratch / "CesiumLogoFlat.png"), read_file(folder / "CesiumLogoFlat.png"));
  expect_same_content(load_asset(folder / "BoxTextured.gltf"), load_asset(scratch / "BoxTextured.gltf"));
}

TEST(SaveRoundTrip, GltfJsonWritesEachArrayOfNumbersOnOneLineAndParsesToTheSameDocument) {
  // 2CylinderEngine has node matrices, accessor min/max and colour factors: arrays of numbers.
  ScratchDir scratch;
  const fs::path input = assets_dir() / "2CylinderEngine" / "specgloss" / "2CylinderEngine.gltf";
  Asset asset = load_asset(input);
  save_asset(asset, scratch / "out.gltf");
  const std::string text = test::read_text(scratch / "out.gltf");
  const auto document = nlohmann::json::parse(text);
  EXPECT_EQ(text, text_with_numbers_inline(document.dump(2)) + "\n");
  EXPECT_NE(text.find("\"matrix\": [1.0, 0.0, 0.0, 0.0, 0.0,"), std::string::npos);
  expect_same_content(load_asset(input), load_asset(scratch / "out.gltf"));
}

TEST(SaveRoundTrip, FailedSaveLeavesNoFileBehind) {
  ScratchDir scratch;
  Asset asset = load_asset(assets_dir() / "Box" / "specgloss" / "Box.gltf");
  test::write_text(scratch / "not-a-folder", "a file where the output folder should be");
  EXPECT_ANY_THROW(save_asset(asset, scratch / "not-a-folder" / "Box.gltf"));
  EXPECT_EQ(test::files_under(scratch.path()).size(), 1u);
}

TEST(AtomicWrites, AFailedCommitPutsBackEveryFileItHadAlreadyRenamed) {
  // An output's side files are renamed before its main file: when a later rename fails (here a
  // folder stands where the last file goes), the earlier ones must not stay half-written.
  ScratchDir scratch;
  test::write_text(scratch / "replaced.png", "the earlier output");
  fs::create_directories(scratch / "blocked.gltf");
  const auto bytes = [](const std::string& text) {
    return std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  };
  const std::string replacement = "a new output", created = "a new file";
  {
    AtomicWriteSet files;
    files.stage(scratch / "replaced.png", bytes(replacement));
    files.stage(scratch / "created.bin", bytes(created));
    files.stage(scratch / "blocked.gltf", bytes(created));
    EXPECT_THROW(files.commit(), OutputError);
  }
  EXPECT_EQ(test::read_text(scratch / "replaced.png"), "the earlier output");
  EXPECT_FALSE(fs::exists(scratch / "created.bin"));
  EXPECT_TRUE(fs::is_directory(scratch / "blocked.gltf"));
  EXPECT_EQ(test::files_under(scratch.path()).size(), 1u) << "no temporary is left";

  AtomicWriteSet files;  // and a commit that succeeds replaces and creates, leaving no temporary
  files.stage(scratch / "replaced.png", bytes(replacement));
  files.stage(scratch / "created.bin", bytes(created));
  EXPECT_EQ(files.commit().size(), 2u);
  EXPECT_EQ(test::read_text(scratch / "replaced.png"), replacement);
  EXPECT_EQ(test::read_text(scratch / "created.bin"), created);
  EXPECT_EQ(test::files_under(scratch.path()).size(), 2u);
}

TEST(AtomicWrites, ALinkIsNeitherRenamedOverNorWrittenThrough) {
  // Renamed over, the link would no longer lead to its file; written through, it may lead to a file
  // the run reads (a texture) or writes under another name (another output).
  ScratchDir scratch;
  test::write_text(scratch / "texture.png", "an input");
  fs::create_symlink("texture.png", scratch / "heat-map.png");
  fs::create_symlink("missing.json", scratch / "dangling.json");
  const std::uint8_t byte = 0;
  AtomicWriteSet files;
  EXPECT_THROW(files.stage(scratch / "heat-map.png", std::span(&byte, 1)), OutputError);
  EXPECT_THROW(files.stage(scratch / "dangling.json", std::span(&byte, 1)), OutputError);
  EXPECT_EQ(test::read_text(scratch / "texture.png"), "an input");
  EXPECT_TRUE(fs::is_symlink(scratch / "heat-map.png"));
}

TEST(AtomicWrites, APipeIsWrittenIntoNotReplaced) {
  // `--report /dev/stdout | jq`, or a FIFO: there is no file to rename over, and replacing the
  // pipe's name would hide the output from its reader.
  ScratchDir scratch;
  const fs::path fifo = scratch / "report.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] {
    std::ifstream in(fifo);
    received.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  });
  const std::string text = "a report through a pipe";
  AtomicWriteSet files;
  files.stage(fifo, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  EXPECT_EQ(files.commit(), std::vector<fs::path>{fifo});
  reader.join();
  EXPECT_EQ(received, text);
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(test::files_under(scratch.path()).size(), 0u) << "no temporary is left";
}

}  // namespace
}  // namespace gltf_pbr
