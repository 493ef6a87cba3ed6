// Conversion of the real spec-gloss assets in ../shared/assets.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <tuple>

#include "converter/convert.hpp"
#include "converter/evaluate.hpp"
#include "converter/legacy_material.hpp"
#include "core/draco.hpp"
#include "test_support.hpp"

namespace gltf_pbr {
namespace {

using test::assets_dir;
using test::ScratchDir;

using test::kSpecGloss;
using test::numbers;

// Every spec-gloss input: the eleven models, the GLB and the Draco variants.
std::vector<fs::path> spec_gloss_inputs() {
  std::vector<fs::path> inputs;
  for (const auto& model : fs::directory_iterator(assets_dir()))
    for (const char* variant : {"specgloss", "specgloss-glb-generated", "specgloss-draco-generated"})
      if (fs::is_directory(model.path() / variant))
        for (const auto& file : fs::directory_iterator(model.path() / variant))
          if (file.path().extension() == ".gltf" || file.path().extension() == ".glb") inputs.push_back(file.path());
  std::sort(inputs.begin(), inputs.end());
  return inputs;
}

fs::path asset_file(const std::string& model, const std::string& variant = "specgloss") {
  for (const auto& file : fs::directory_iterator(assets_dir() / model / variant))
    if (file.path().extension() == ".gltf" || file.path().extension() == ".glb") return file.path();
  ADD_FAILURE() << "no asset " << model << "/" << variant;
  return {};
}

int count_spec_gloss_materials(const tinygltf::Model& model) {
  int n = 0;
  for (const auto& material : model.materials) n += material.extensions.count(kSpecGloss) ? 1 : 0;
  return n;
}

bool lists(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// The bytes an accessor's bufferView covers, for byte-identity checks across containers.
std::vector<std::uint8_t> view_bytes(const tinygltf::Model& model, int view_index) {
  const auto& view = model.bufferViews.at(static_cast<size_t>(view_index));
  const auto& data = model.buffers.at(static_cast<size_t>(view.buffer)).data;
  return {data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset),
          data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset + view.byteLength)};
}

TEST(ConvertSharedAssets, FindsEveryInputVariant) {
  const auto inputs = spec_gloss_inputs();
  EXPECT_EQ(inputs.size(), 13u);  // 11 models + a GLB + a Draco variant
}

TEST(ConvertSharedAssets, EverySpecGlossAssetConvertsInBothTargetsAndReloadsWithoutSpecGloss) {
  ScratchDir scratch;
  for (const fs::path& input : spec_gloss_inputs()) {
    for (Target target : {Target::Metalness, Target::Specular}) {
      SCOPED_TRACE(input.string() + (target == Target::Metalness ? " metalness" : " specular"));
      Asset asset = load_asset(input);
      const int legacy_materials = count_spec_gloss_materials(asset.model);
      ConvertOptions options;
      options.target = target;
      const ConversionReport report = convert(asset, options);
      EXPECT_EQ(static_cast<int>(report.materials.size()), legacy_materials);
      for (const MaterialReport& m : report.materials) {
        EXPECT_TRUE(m.outcome == MaterialOutcome::Metalness || m.outcome == MaterialOutcome::Specular)
            << m.index << " " << material_outcome_name(m.outcome);
        ASSERT_TRUE(m.error_a && m.error_b) << m.index << ": converted but not measured";
        for (double v : {m.error_a->diffuse.mean, m.error_a->diffuse.max, m.error_a->f0.max, m.error_b->f0.max})
          EXPECT_TRUE(std::isfinite(v));
        if (target == Target::Metalness) {
          EXPECT_EQ(m.outcome, MaterialOutcome::Metalness);
        }
      }
      const fs::path output =
          scratch /
          (input.parent_path().parent_path().filename().string() + (target == Target::Metalness ? "-m" : "-s")) /
          input.filename();
      save_asset(asset, output);

      const Asset converted = load_asset(output);
      EXPECT_EQ(count_spec_gloss_materials(converted.model), 0);
      EXPECT_FALSE(lists(converted.model.extensionsUsed, kSpecGloss));
      EXPECT_FALSE(lists(converted.model.extensionsRequired, kSpecGloss));
      bool uses_specular = false;
      for (const auto& material : converted.model.materials) {
        uses_specular = uses_specular || material.extensions.count("KHR_materials_specular");
        for (double v : material.pbrMetallicRoughness.baseColorFactor) EXPECT_TRUE(std::isfinite(v));
        EXPECT_TRUE(std::isfinite(material.pbrMetallicRoughness.metallicFactor));
      }
      EXPECT_EQ(lists(converted.model.extensionsUsed, "KHR_materials_specular"), uses_specular);
      if (target == Target::Metalness) {
        EXPECT_FALSE(uses_specular);
      }
    }
  }
}

TEST(LazyWork, FactorOnlyAssetsDecodeNoImage) {
  for (const char* model : {"Box", "BoxInterleaved", "RiggedSimple", "2CylinderEngine"}) {
    Asset asset = load_asset(asset_file(model));
    const long before = work_counters().images_decoded;
    convert(asset);
    EXPECT_EQ(work_counters().images_decoded - before, 0) << model;
  }
}

TEST(LazyWork, DracoAssetDecodesNoMeshAndStaysCompressedByteForByte) {
  ScratchDir scratch;
  const fs::path input = asset_file("2CylinderEngine", "specgloss-draco-generated");
  Asset asset = load_asset(input);
  const long before = work_counters().meshes_decoded;
  convert(asset);
  save_asset(asset, scratch / "engine.gltf");
  EXPECT_EQ(work_counters().meshes_decoded - before, 0);

  const Asset original = load_asset(input), converted = load_asset(scratch / "engine.gltf");
  EXPECT_TRUE(lists(converted.model.extensionsUsed, "KHR_draco_mesh_compression"));
  ASSERT_EQ(converted.model.meshes.size(), original.model.meshes.size());
  for (size_t m = 0; m < original.model.meshes.size(); ++m)
    for (size_t p = 0; p < original.model.meshes[m].primitives.size(); ++p) {
      const auto& before_ext = original.model.meshes[m].primitives[p].extensions.at("KHR_draco_mesh_compression");
      const auto& after_ext = converted.model.meshes[m].primitives[p].extensions.at("KHR_draco_mesh_compression");
      EXPECT_EQ(view_bytes(converted.model, after_ext.Get("bufferView").GetNumberAsInt()),
                view_bytes(original.model, before_ext.Get("bufferView").GetNumberAsInt()));
    }
}

TEST(Draco, DecodesTheSharedDracoMeshOnDemandAndCountsIt) {
  const Asset asset = load_asset(asset_file("2CylinderEngine", "specgloss-draco-generated"));
  const long before = work_counters().meshes_decoded;
  const DecodedPrimitive primitive = decode_draco_primitive(asset, 0, 0);
  EXPECT_EQ(work_counters().meshes_decoded - before, 1);
  EXPECT_EQ(primitive.indices.size() % 3, 0u);
  ASSERT_TRUE(primitive.attributes.count("POSITION"));
  const auto& accessor =
      asset.model.accessors.at(static_cast<size_t>(asset.model.meshes[0].primitives[0].attributes.at("POSITION")));
  EXPECT_EQ(primitive.attributes.at("POSITION").size(), accessor.count * 3);
}

TEST(Untouched, BuffersAndUntouchedImagesAreWrittenByteForByte) {
  ScratchDir scratch;
  const fs::path input = asset_file("Avocado");
  Asset asset = load_asset(input);
  convert(asset);
  save_asset(asset, scratch / "Avocado.gltf");
  EXPECT_EQ(read_file(scratch / "Avocado.bin"), read_file(input.parent_path() / "Avocado.bin"));
  EXPECT_EQ(read_file(scratch / "Avocado_normal.png"), read_file(input.parent_path() / "Avocado_normal.png"));
}

TEST(Untouched, GlbMeshDataKeepsItsBytes) {
  ScratchDir scratch;
  const fs::path input = asset_file("CesiumMilkTruck", "specgloss-glb-generated");
  Asset asset = load_asset(input);
  convert(asset);
  save_asset(asset, scratch / "truck.glb");
  const Asset original = load_asset(input), converted = load_asset(scratch / "truck.glb");
  ASSERT_EQ(converted.model.accessors.size(), original.model.accessors.size());
  for (size_t i = 0; i < original.model.accessors.size(); ++i)
    EXPECT_EQ(view_bytes(converted.model, converted.model.accessors[i].bufferView),
              view_bytes(original.model, original.model.accessors[i].bufferView))
        << "accessor " << i;
}

TEST(Idempotence, ConvertingAConvertedFileChangesNothing) {
  ScratchDir scratch;
  for (const char* model : {"Duck", "Box", "VC"}) {
    Asset first = load_asset(asset_file(model));
    convert(first);
    const fs::path once = scratch / model / "once.gltf";
    save_asset(first, once);
    Asset again = load_asset(once);
    const ConversionReport report = convert(again);
    EXPECT_FALSE(report.changed()) << model;
    copy_asset_verbatim(again, scratch / (std::string(model) + "-twice") / "twice.gltf");
    EXPECT_EQ(read_file(scratch / (std::string(model) + "-twice") / "twice.gltf"), read_file(once)) << model;
  }
}

// compare reads the texels the bake reads and samples them as the bake samples its error, so on
// convert's own output it measures what the report says, material by material: the report gives the
// error of the texels the file holds, a JPEG base colour's included (CesiumMan, VC), in either target.
TEST(Compare, OnConvertsOwnOutputGivesTheFiguresOfConvertsReport) {
  ScratchDir scratch;
  // Metalness outputs as a core-only viewer sees them; --target specular's as a full viewer does
  // (a material on the extension route reports the route's error).
  for (const auto& [target, viewer] :
       {std::pair{Target::Metalness, Viewer::CoreOnly}, std::pair{Target::Specular, Viewer::Full}})
    for (const fs::path& input : spec_gloss_inputs()) {
      SCOPED_TRACE(input.string() + (target == Target::Metalness ? " metalness" : " specular"));
      Asset asset = load_asset(input);
      ConvertOptions options;
      options.target = target;
      const ConversionReport report = convert(asset, options);
      const fs::path output = scratch / (target == Target::Metalness ? "m" : "s") /
                              input.parent_path().parent_path().filename() / input.filename();
      save_asset(asset, output);
      const std::vector<MaterialComparison> compared =
          compare_conversion(load_asset(input), load_asset(output), viewer);
      ASSERT_EQ(compared.size(), report.materials.size());
      for (size_t i = 0; i < compared.size(); ++i) {
        const MaterialReport& m = report.materials[i];
        const MaterialComparison& c = compared[i];
        ASSERT_EQ(c.index, m.index);
        ASSERT_TRUE(m.error_a);
        EXPECT_EQ(c.samples, m.error_samples) << "material " << m.index;
        const auto agree = [&](const char* what, const ErrorStats& compared_stats, const ErrorStats& reported) {
          for (const auto& [statistic, x, y] : {std::tuple{"mean", compared_stats.mean, reported.mean},
                                                std::tuple{"p95", compared_stats.p95, reported.p95},
                                                std::tuple{"max", compared_stats.max, reported.max}})
            EXPECT_NEAR(x, y, 1e-3 + 1e-4 * y) << "material " << m.index << " " << what << " " << statistic;
        };
        agree("diffuse", c.error.diffuse, m.error_a->diffuse);
        agree("F0", c.error.f0, m.error_a->f0);
      }
    }
}

TEST(Sharing, IdenticalInputsShareOneOutputTexture) {
  Asset asset = load_asset(asset_file("Duck"));
  asset.model.materials.push_back(asset.model.materials[0]);  // a second material, same inputs
  const ConversionReport report = convert(asset);
  ASSERT_EQ(report.materials.size(), 2u);
  const auto& a = asset.model.materials[0].pbrMetallicRoughness;
  const auto& b = asset.model.materials[1].pbrMetallicRoughness;
  EXPECT_EQ(a.baseColorTexture.index, b.baseColorTexture.index);
  EXPECT_EQ(a.metallicRoughnessTexture.index, b.metallicRoughnessTexture.index);
  EXPECT_LE(report.textures_baked, 2);
}

// Duck with a second material: a copy of its first whose spec-gloss object `change` edits.
Asset duck_with_a_second_material(const std::function<void(Asset&, tinygltf::Value::Object&)>& change) {
  Asset asset = load_asset(asset_file("Duck"));
  tinygltf::Material copy = asset.model.materials[0];
  auto extension = copy.extensions.at(kSpecGloss).Get<tinygltf::Value::Object>();
  change(asset, extension);
  copy.extensions[kSpecGloss] = tinygltf::Value(std::move(extension));
  asset.model.materials.push_back(copy);
  return asset;
}

// The two materials' base colour and metallicRoughness textures are the same ones, and the second
// material shares both.
void expect_one_set_of_maps(const Asset& asset, const ConversionReport& report) {
  ASSERT_EQ(report.materials.size(), 2u);
  const auto& a = asset.model.materials[0].pbrMetallicRoughness;
  const auto& b = asset.model.materials[1].pbrMetallicRoughness;
  EXPECT_EQ(a.baseColorTexture.index, b.baseColorTexture.index);
  ASSERT_GE(a.metallicRoughnessTexture.index, 0);
  EXPECT_EQ(a.metallicRoughnessTexture.index, b.metallicRoughnessTexture.index);
  EXPECT_EQ(report.materials[0].outputs.base_color, TextureOutcome::Baked);
  EXPECT_EQ(report.materials[1].outputs.base_color, TextureOutcome::Shared);
  EXPECT_EQ(report.materials[1].outputs.metallic_roughness, TextureOutcome::Shared);
  EXPECT_EQ(report.textures_baked, 2);
}

// Glossiness does not enter the normal-incidence solve, and a glossiness factor is carried by the
// roughness factor over a map that holds roughness 1: two materials that differ only in it share
// one bake, and each keeps its own roughness.
TEST(Sharing, MaterialsThatDifferOnlyInTheirGlossinessFactorShareOneBake) {
  Asset asset = duck_with_a_second_material(
      [](Asset&, tinygltf::Value::Object& e) { e["glossinessFactor"] = tinygltf::Value(0.8); });
  const ConversionReport report = convert(asset);
  expect_one_set_of_maps(asset, report);
  EXPECT_EQ(report.materials[1].times.solve_ms, 0.0);  // one bake, not two that came out alike
  EXPECT_NEAR(asset.model.materials[0].pbrMetallicRoughness.roughnessFactor, 0.7, 1e-6);  // Duck's glossiness 0.3
  EXPECT_NEAR(asset.model.materials[1].pbrMetallicRoughness.roughnessFactor, 0.2, 1e-6);
}

// Exporters repeat an image per material: image entries that hold the same bytes are one input,
// decoded once and baked once.
TEST(Sharing, ImageEntriesThatHoldTheSameBytesAreOneInput) {
  Asset asset = duck_with_a_second_material([](Asset& duck, tinygltf::Value::Object& e) {
    duck.model.images.push_back(duck.model.images.at(0));
    tinygltf::Texture texture = duck.model.textures.at(0);
    texture.source = static_cast<int>(duck.model.images.size()) - 1;
    duck.model.textures.push_back(texture);
    auto diffuse = e.at("diffuseTexture").Get<tinygltf::Value::Object>();
    diffuse["index"] = tinygltf::Value(static_cast<int>(duck.model.textures.size()) - 1);
    e["diffuseTexture"] = tinygltf::Value(std::move(diffuse));
  });
  const ConversionReport report = convert(asset);
  expect_one_set_of_maps(asset, report);
  EXPECT_EQ(report.images_decoded, 1);
  EXPECT_EQ(report.materials[1].times.solve_ms, 0.0);  // nothing solved again
}

// Two bakes whose maps come out byte-identical: the diffuse factors differ only in an alpha that the
// RGB diffuse texture does not carry (the factor carries it). The second bake's maps are the
// first's images, written once.
TEST(Sharing, ABakedImageEqualToOneAlreadyWrittenIsSharedNotWrittenAgain) {
  Asset asset = duck_with_a_second_material([](Asset&, tinygltf::Value::Object& e) {
    e["diffuseFactor"] = numbers({1.0, 1.0, 1.0, 0.5});
  });
  const ConversionReport report = convert(asset);
  expect_one_set_of_maps(asset, report);
  EXPECT_DOUBLE_EQ(asset.model.materials[1].pbrMetallicRoughness.baseColorFactor.at(3), 0.5);
  EXPECT_GT(report.materials[1].times.solve_ms, 0.0);  // a bake of its own
  EXPECT_EQ(report.textures_shared, 1);
  std::set<ImageContentKey> distinct;
  for (const auto& image : asset.model.images) distinct.insert(image_content_key(image.image));
  EXPECT_EQ(distinct.size(), asset.model.images.size());
}

// VC's JPEG diffuse textures over specular 0: re-encoding the baked base colour as JPEG costs more
// error than the bake removes, so those materials keep their diffuse image as it is, metallic 0,
// and no image is written for them; its specular-0.57 material still bakes.
TEST(DielectricCopy, AJpegDiffuseIsKeptAsItIsWhereItsReEncodedBakeMeasuresWorse) {
  const Asset original = load_asset(asset_file("VC"));
  Asset asset = original;
  const ConversionReport report = convert(asset);
  int kept = 0, baked = 0;
  for (const MaterialReport& m : report.materials) {
    const auto& pbr = asset.model.materials[static_cast<size_t>(m.index)].pbrMetallicRoughness;
    const LegacyMaterial legacy = read_legacy_material(original, m.index);
    if (m.note.rfind("the diffuse image kept as it is", 0) != 0) {
      baked += m.outputs.base_color == TextureOutcome::Baked;
      continue;
    }
    ++kept;
    ASSERT_TRUE(legacy.diffuse_texture);
    EXPECT_EQ(pbr.baseColorTexture.index, legacy.diffuse_texture->index) << m.name;
    EXPECT_EQ(m.outputs.base_color, TextureOutcome::InputReused) << m.name;
    EXPECT_EQ(m.outputs.metallic_roughness, TextureOutcome::Factor) << m.name;
    EXPECT_EQ(pbr.metallicRoughnessTexture.index, -1) << m.name;
    EXPECT_EQ(pbr.metallicFactor, 0.0) << m.name;
    EXPECT_NEAR(pbr.roughnessFactor, 1.0 - legacy.glossiness_factor, 1e-6) << m.name;
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(pbr.baseColorFactor[static_cast<size_t>(c)], legacy.diffuse_factor[c], 1e-6) << m.name;
    // The note gives both figures on part of the samples, the kept image's no higher; the report
    // gives the kept image's on all of them.
    double copy = 0, as_baked = 0;
    size_t part = 0;
    ASSERT_EQ(std::sscanf(m.note.c_str(),
                          "the diffuse image kept as it is, metallic 0: diffuse + F0 means %lf ΔE2000, against %lf for "
                          "the base colour as baked and re-encoded as JPEG (on %zu error samples)",
                          &copy, &as_baked, &part),
              3)
        << m.note;
    EXPECT_LE(copy, as_baked) << m.name;
    EXPECT_LT(part, m.error_samples) << m.name;
    EXPECT_NEAR(m.error_a->diffuse.mean + m.error_a->f0.mean, copy, 0.5) << m.name;
  }
  EXPECT_GT(kept, 100);
  EXPECT_GT(baked, 0);
  int jpeg_images = 0;  // the baked materials' base colours, and none for the kept ones
  for (const auto& image : asset.model.images) jpeg_images += image.name.rfind("baseColor", 0) == 0;
  EXPECT_EQ(jpeg_images, baked);
}

TEST(Fallback, AuthorsOldMetalRoughTexturesAreDroppedWhenUnused) {
  ScratchDir scratch;
  Asset asset = load_asset(asset_file("Avocado"));
  const ConversionReport report = convert(asset);
  save_asset(asset, scratch / "Avocado.gltf");
  EXPECT_GE(report.images_removed, 2);
  EXPECT_FALSE(fs::exists(scratch / "Avocado_baseColor.png"));
  EXPECT_FALSE(fs::exists(scratch / "Avocado_roughnessMetallic.png"));
  for (const auto& image : load_asset(scratch / "Avocado.gltf").model.images)
    EXPECT_TRUE(image.uri.find("roughnessMetallic") == std::string::npos) << image.uri;
}

TEST(ExtensionLists, DeclaredButUnusedSpecGlossIsRemoved) {
  Asset asset = load_asset(asset_file("BoxInterleaved"));
  ASSERT_TRUE(lists(asset.model.extensionsRequired, kSpecGloss));
  const ConversionReport report = convert(asset);
  EXPECT_TRUE(report.changed());
  EXPECT_FALSE(lists(asset.model.extensionsUsed, kSpecGloss));
  EXPECT_FALSE(lists(asset.model.extensionsRequired, kSpecGloss));
}

TEST(SpecularTarget, AddsExtensionsOnlyToMaterialsThatNeedThem) {
  Asset asset = load_asset(asset_file("2CylinderEngine"));
  ConvertOptions options;
  options.target = Target::Specular;
  const ConversionReport report = convert(asset, options);
  int specular = 0, metalness = 0;
  for (const MaterialReport& m : report.materials) {
    const auto& material = asset.model.materials[static_cast<size_t>(m.index)];
    const bool has = material.extensions.count("KHR_materials_specular") > 0;
    EXPECT_EQ(has, m.outcome == MaterialOutcome::Specular) << m.index;
    EXPECT_EQ(material.extensions.count("KHR_materials_ior") > 0, has) << m.index;
    (has ? specular : metalness)++;
  }
  EXPECT_GT(specular, 0);   // coloured specular 0.8 on diffuse 0.85 cannot fit metalness
  EXPECT_GT(metalness, 0);  // the plain ones can
}

// Under the appearance model the extension route is not exact (its diffuse loses the Fresnel of
// its own F0), so --target specular takes it only where it lowers the appearance p95 by more than
// the tolerance, and every material's note says which and by how much. Factor-only materials are
// checked against the two appearances computed directly; what a routed one reports is the route's.
TEST(SpecularTarget, UnderTheAppearanceModelTakesTheRouteOnlyWhereItLowersTheAppearanceError) {
  int routed = 0, kept = 0;
  for (const char* name : {"2CylinderEngine", "Box", "CesiumMilkTruck", "Avocado"}) {
    const Asset original = load_asset(asset_file(name));
    Asset asset = load_asset(asset_file(name));
    ConvertOptions options;
    options.target = Target::Specular;
    options.solver = solver_preset(SolverEffort::Balanced, ErrorModel::Appearance);
    const ConversionReport report = convert(asset, options);
    for (const MaterialReport& m : report.materials) {
      EXPECT_FALSE(m.note.empty()) << name << " material " << m.index;
      ASSERT_TRUE(m.error_a && m.error_a->appearance) << name << " material " << m.index;
      const LegacyMaterial legacy = read_legacy_material(original, m.index);
      if (legacy.diffuse_texture || legacy.spec_gloss_texture) continue;
      const SpecGloss factors{glm::vec3(legacy.diffuse_factor), legacy.specular_factor, legacy.glossiness_factor};
      const Appearance seen = legacy_appearance(factors);
      const double metalness = appearance_delta_e(seen, core_appearance(solve(factors, options.solver)));
      const double route = appearance_delta_e(seen, specular_extension_appearance(factors));
      const bool takes = m.outcome == MaterialOutcome::Specular;
      EXPECT_EQ(takes, metalness - route > options.specular_tolerance)
          << name << " material " << m.index << ": " << metalness << " against " << route;
      EXPECT_NEAR(m.error_a->appearance->mean, takes ? route : metalness, 1e-3) << name << " material " << m.index;
      (takes ? routed : kept)++;
    }
  }
  EXPECT_GT(routed, 0);
  EXPECT_GT(kept, 0);
}

TEST(TextureMapping, DifferentTexCoordSetsLeaveTheMaterialLegacyWithAWarning) {
  Asset asset = load_asset(asset_file("Avocado"));
  auto& extension = asset.model.materials[0].extensions.at(kSpecGloss);
  tinygltf::Value::Object object = extension.Get<tinygltf::Value::Object>();
  tinygltf::Value::Object diffuse = object.at("diffuseTexture").Get<tinygltf::Value::Object>();
  diffuse["texCoord"] = tinygltf::Value(1);
  object["diffuseTexture"] = tinygltf::Value(diffuse);
  extension = tinygltf::Value(object);
  const long before = work_counters().images_decoded;
  const ConversionReport report = convert(asset);
  ASSERT_EQ(report.materials.size(), 1u);
  EXPECT_EQ(report.materials[0].outcome, MaterialOutcome::Legacy);
  EXPECT_FALSE(report.warnings.empty());
  EXPECT_TRUE(asset.model.materials[0].extensions.count(kSpecGloss));
  EXPECT_TRUE(lists(asset.model.extensionsUsed, kSpecGloss));
  EXPECT_EQ(work_counters().images_decoded - before, 0);
}

TEST(Report, FactorOnlyMaterialsReportOneTexelAndTheirError) {
  Asset asset = load_asset(asset_file("2CylinderEngine"));
  const ConversionReport report = convert(asset);
  ASSERT_FALSE(report.materials.empty());
  for (const MaterialReport& m : report.materials) {
    EXPECT_EQ(m.texels, 1);
    EXPECT_EQ(m.error_samples, 1u);
  }
}

TEST(Report, TexturedMaterialsReportTexelsAndSampledError) {
  Asset asset = load_asset(asset_file("Avocado"));
  const ConversionReport report = convert(asset);
  ASSERT_EQ(report.materials.size(), 1u);
  EXPECT_EQ(report.materials[0].texels, 2048LL * 2048);
  EXPECT_GE(report.materials[0].error_samples, 65536u);
  EXPECT_GT(report.materials[0].times.solve_ms, 0.0);
  EXPECT_EQ(report.images_decoded, 2);
}

// The appearance model's run reports both models' figures per material: the normal-incidence
// ΔE2000 under readings A and B and the appearance ΔE2000 under reading A (not measured under B:
// none, never a 0). The normal-incidence run leaves the appearance unmeasured (its solve cache is
// not keyed by glossiness, on which the appearance depends; keying it tripled Avocado's solve).
// Each model lowers its own error: the normal-incidence one on a textured asset (Avocado, sampled
// texels) and a factor-only one (Box, a red material with a grey 0.2 specular); the appearance one
// on Box, against the appearance of the normal-incidence solve computed directly.
TEST(Report, TheAppearanceRunReportsBothModelsErrorsAndEachModelLowersItsOwn) {
  for (const char* model_name : {"Avocado", "Box"}) {
    ConversionReport by_model[2];
    for (int k = 0; k < 2; ++k) {
      Asset asset = load_asset(asset_file(model_name));
      ConvertOptions options;
      options.solver =
          solver_preset(SolverEffort::Balanced, k == 0 ? ErrorModel::NormalIncidence : ErrorModel::Appearance);
      by_model[k] = convert(asset, options);
      for (const MaterialReport& m : by_model[k].materials) {
        ASSERT_TRUE(m.error_a && m.error_b) << model_name;
        EXPECT_EQ(m.error_a->appearance.has_value(), k == 1) << model_name;
        EXPECT_FALSE(m.error_b->appearance) << model_name;
        if (k == 1) {
          EXPECT_TRUE(std::isfinite(m.error_a->appearance->max)) << model_name;
        }
      }
    }
    const ReflectanceError &ni = *by_model[0].materials[0].error_a, &seen = *by_model[1].materials[0].error_a;
    EXPECT_LE(ni.diffuse.mean + ni.f0.mean, seen.diffuse.mean + seen.f0.mean) << model_name;
  }
  const SpecGloss box{{0.8f, 0.0f, 0.0f}, glm::vec3(0.2f), 1.0f};  // Box's material, as it reads
  Asset asset = load_asset(asset_file("Box"));
  ConvertOptions options;
  options.solver = solver_preset(SolverEffort::Balanced, ErrorModel::Appearance);
  const ConversionReport report = convert(asset, options);
  const double normal_incidence_look = appearance_delta_e(legacy_appearance(box), core_appearance(solve(box)));
  EXPECT_LT(report.materials[0].error_a->appearance->mean, normal_incidence_look);
}

TEST(Report, SaysPerMaterialWhichTexturesWereBakedSharedReusedOrMadeFactors) {
  {  // The truck's diffuse over the core dielectric F0 is its own base colour; metalness 0 everywhere.
    Asset asset = load_asset(asset_file("CesiumMilkTruck"));
    const ConversionReport report = convert(asset);
    std::map<std::string, MaterialOutputs> by_name;
    for (const MaterialReport& m : report.materials) by_name[m.name] = m.outputs;
    EXPECT_EQ(by_name.at("truck").base_color, TextureOutcome::InputReused);
    EXPECT_EQ(by_name.at("truck").metallic_roughness, TextureOutcome::Factor);
    EXPECT_EQ(by_name.at("glass").base_color, TextureOutcome::None);  // factors only
    EXPECT_EQ(report.textures_baked, 0);
  }
  {  // VC: many materials read one image with the same factors; the first bakes, the rest share.
    Asset asset = load_asset(asset_file("VC"));
    const ConversionReport report = convert(asset);
    int baked = 0, shared = 0;
    for (const MaterialReport& m : report.materials) {
      baked += m.outputs.base_color == TextureOutcome::Baked;
      shared += m.outputs.base_color == TextureOutcome::Shared;
    }
    EXPECT_GT(shared, 0);
    int baked_images = 0;  // every baked base colour is one new image
    for (const auto& image : asset.model.images) baked_images += image.name.rfind("baseColor", 0) == 0;
    EXPECT_EQ(baked, baked_images);
  }
}

// Which shared objects `gltf-pbr <arguments>` opens, as the dynamic loader logs them (ld.so(8),
// LD_DEBUG=files): the OpenImageIO module and its ~260 libraries cost 0.3 s and 128 MiB.
bool loads_the_image_module(const std::string& arguments, const ScratchDir& scratch) {
  const fs::path log = scratch / "ld-debug.txt";
  const std::string command =
      "LD_DEBUG=files " + test::quoted(GLTF_PBR_CLI) + " " + arguments + " >/dev/null 2>" + test::quoted(log);
  const int status = std::system(command.c_str());  // validate exits 1 for files with errors
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) <= 1) << command;
  const std::string opened = test::read_text(log);
  EXPECT_NE(opened.find("file="), std::string::npos) << "the loader logged nothing";
  return opened.find("libgltf_pbr_images") != std::string::npos || opened.find("libOpenImageIO") != std::string::npos;
}

TEST(ImageLibraries, PngAndJpegAssetsConvertAndValidateWithoutLoadingOpenImageIo) {
  ScratchDir scratch;
  for (const char* model : {"BoxTextured", "CesiumMan", "VC", "Avocado"})  // PNG, JPEG, both, 2K PNGs
    EXPECT_FALSE(loads_the_image_module(
        "convert " + test::quoted(asset_file(model)) + " -o " + test::quoted(scratch / model / "out.gltf"), scratch))
        << model;
  for (const char* model : {"CesiumMan", "Avocado"})  // every texture check, and previews' decodes
    EXPECT_FALSE(loads_the_image_module("validate -f json -q " + test::quoted(asset_file(model)), scratch)) << model;
  // The check sees a load when there is one: a WebP texture needs the module.
  EXPECT_TRUE(loads_the_image_module(
      "convert " + test::quoted(fs::path(GLTF_PBR_SOURCE_DIR) / "tests/hostile_inputs/webp_data_uri.gltf") + " -o " +
          test::quoted(scratch / "webp" / "out.gltf"),
      scratch));
}

}  // namespace
}  // namespace gltf_pbr
