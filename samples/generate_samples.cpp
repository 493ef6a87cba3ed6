// generate-samples OUTPUT_FOLDER: writes small KHR_materials_pbrSpecularGlossiness assets, one per
// material class of DESIGN.md ("Why albedo + metalness"), plus one textured crate, then index.txt.
//
// The output is a pure function of this file: no clock, no randomness, fixed iteration order, so two
// runs write the same bytes and the samples can be regenerated at build time instead of committed.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/asset.hpp"
#include "core/color.hpp"
#include "core/files.hpp"
#include "core/image.hpp"

namespace {

using gltf_pbr::Bytes;
namespace fs = gltf_pbr::fs;

constexpr const char* kSpecGloss = "KHR_materials_pbrSpecularGlossiness";

// ---------------------------------------------------------------------------------------------
// Material classes
// ---------------------------------------------------------------------------------------------

// One factor-only legacy material. Factors are linear, as the extension defines them.
struct FactorSample {
  const char* file_stem;  // "metal-gold" -> metal-gold.gltf, metal-gold.bin
  const char* name;       // material name: the class name
  glm::dvec4 diffuse;     // diffuseFactor
  glm::dvec3 specular;    // specularFactor = F0
  double glossiness;      // glossinessFactor
};

constexpr glm::dvec4 kNoDiffuse{0.0, 0.0, 0.0, 1.0};  // conductors absorb what is refracted

// Dielectric F0 from DESIGN.md, "Why albedo + metalness": water 0.02, plastic 0.04, gems 0.05-0.08,
// diamond-like 0.10-0.20, crystalline silicon ~0.35-0.43. Dielectric F0 is achromatic; the diffuse
// colours are plausible albedos inside the rules' linear 0.012-0.9 range.
// Metal F0: DESIGN.md's table (Hoffman, "Physics and Math of Shading"), linear RGB, copied verbatim.
// Gold's red 1.022 lies outside sRGB on purpose: a converter must cope with it without NaN.
// Glossiness is spread over 0.3-0.9 so that roughness conversion is exercised across its range.
const std::array<FactorSample, 16> kFactorSamples{{
    {"dielectric-water", "water", {0.03, 0.08, 0.10, 1.0}, glm::dvec3(0.02), 0.90},
    {"dielectric-plastic", "plastic", {0.50, 0.05, 0.05, 1.0}, glm::dvec3(0.04), 0.60},
    {"dielectric-gem", "gem", {0.05, 0.35, 0.12, 1.0}, glm::dvec3(0.06), 0.85},
    {"dielectric-diamond-like", "diamond-like", {0.70, 0.70, 0.70, 1.0}, glm::dvec3(0.17), 0.88},
    {"semiconductor-silicon", "silicon", {0.15, 0.16, 0.18, 1.0}, glm::dvec3(0.38), 0.70},
    {"metal-titanium", "titanium", kNoDiffuse, {0.542, 0.497, 0.449}, 0.45},
    {"metal-chromium", "chromium", kNoDiffuse, {0.549, 0.556, 0.554}, 0.85},
    {"metal-iron", "iron", kNoDiffuse, {0.562, 0.565, 0.578}, 0.30},
    {"metal-nickel", "nickel", kNoDiffuse, {0.660, 0.609, 0.526}, 0.60},
    {"metal-platinum", "platinum", kNoDiffuse, {0.673, 0.637, 0.585}, 0.70},
    {"metal-silver", "silver", kNoDiffuse, {0.972, 0.960, 0.915}, 0.80},
    {"metal-copper", "copper", kNoDiffuse, {0.955, 0.638, 0.538}, 0.55},
    {"metal-palladium", "palladium", kNoDiffuse, {0.733, 0.697, 0.652}, 0.65},
    {"metal-zinc", "zinc", kNoDiffuse, {0.664, 0.824, 0.850}, 0.40},
    {"metal-gold", "gold", kNoDiffuse, {1.022, 0.782, 0.344}, 0.75},
    {"metal-aluminum", "aluminum", kNoDiffuse, {0.913, 0.922, 0.924}, 0.50},
}};

// ---------------------------------------------------------------------------------------------
// Geometry
// ---------------------------------------------------------------------------------------------

struct MeshData {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> texcoords;
  std::vector<std::uint16_t> indices;
};

// sin/cos of multiples of pi/2 come out as ~1e-16 rather than 0; exact zeros read better in the
// JSON min/max and cost nothing.
double snap_to_zero(double value) { return std::abs(value) < 1e-12 ? 0.0 : value; }

// A UV sphere: `segments` around Y, `rings` from the +Y pole down. The seam column and the pole rows
// are duplicated so each vertex has one UV; u grows eastward as seen from outside and v grows
// downward, matching glTF's top-left UV origin, so textures are not mirrored.
MeshData make_uv_sphere(double radius, int segments, int rings) {
  MeshData mesh;
  for (int ring = 0; ring <= rings; ++ring) {
    const double theta = std::numbers::pi * ring / rings;  // polar angle from +Y
    for (int segment = 0; segment <= segments; ++segment) {
      const double phi = 2.0 * std::numbers::pi * segment / segments;  // 0 at +Z, then towards +X
      const glm::dvec3 direction{snap_to_zero(std::sin(theta) * std::sin(phi)), snap_to_zero(std::cos(theta)),
                                 snap_to_zero(std::sin(theta) * std::cos(phi))};
      mesh.positions.emplace_back(direction * radius);
      mesh.normals.emplace_back(glm::normalize(direction));
      mesh.texcoords.emplace_back(static_cast<double>(segment) / segments, static_cast<double>(ring) / rings);
    }
  }
  const int row = segments + 1;
  for (int ring = 0; ring < rings; ++ring) {
    for (int segment = 0; segment < segments; ++segment) {
      const auto top_left = static_cast<std::uint16_t>(ring * row + segment);
      const auto bottom_left = static_cast<std::uint16_t>(top_left + row);
      const auto bottom_right = static_cast<std::uint16_t>(bottom_left + 1);
      const auto top_right = static_cast<std::uint16_t>(top_left + 1);
      // The quads touching a pole have one collapsed edge; emitting their degenerate half would
      // give zero-area triangles that validators flag.
      if (ring != rings - 1) mesh.indices.insert(mesh.indices.end(), {top_left, bottom_left, bottom_right});
      if (ring != 0) mesh.indices.insert(mesh.indices.end(), {top_left, bottom_right, top_right});
    }
  }
  return mesh;
}

// An axis-aligned cube with 4 vertices per face (flat normals), each face showing the whole texture
// upright when seen from outside.
MeshData make_cube(float half_extent) {
  struct Face {
    glm::vec3 normal, right, up;  // right x up = normal, so the winding below is counter-clockwise
  };
  const std::array<Face, 6> faces{{
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},
      {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},
      {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},
      {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
  }};
  MeshData mesh;
  for (const Face& face : faces) {
    const auto first = static_cast<std::uint16_t>(mesh.positions.size());
    // Corner order: top-left, bottom-left, bottom-right, top-right (UV origin is top-left).
    const std::array<glm::vec2, 4> corners{{{0, 0}, {0, 1}, {1, 1}, {1, 0}}};
    for (const glm::vec2 uv : corners) {
      const glm::vec3 offset = face.right * (2.0f * uv.x - 1.0f) + face.up * (1.0f - 2.0f * uv.y);
      mesh.positions.push_back((face.normal + offset) * half_extent);
      mesh.normals.push_back(face.normal);
      mesh.texcoords.push_back(uv);
    }
    mesh.indices.insert(mesh.indices.end(), {first, static_cast<std::uint16_t>(first + 1), static_cast<std::uint16_t>(first + 2),
                                             first, static_cast<std::uint16_t>(first + 2), static_cast<std::uint16_t>(first + 3)});
  }
  return mesh;
}

// glTF 2.0 spec, "Meshes": front faces wind counter-clockwise. A generator bug here would make
// every sample render inside out, so check each triangle against its vertex normals.
void check_outward_winding(const MeshData& mesh, const char* mesh_name) {
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const auto a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    const glm::vec3 face_normal = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    const glm::vec3 vertex_normals = mesh.normals[a] + mesh.normals[b] + mesh.normals[c];
    if (!(glm::dot(face_normal, vertex_normals) > 0.0f))
      throw std::logic_error(std::string(mesh_name) + ": triangle " + std::to_string(i / 3) +
                             " winds inward or is degenerate");
  }
}

// ---------------------------------------------------------------------------------------------
// Document building
// ---------------------------------------------------------------------------------------------

template <typename T>
void append_raw(Bytes& bytes, const std::vector<T>& values) {
  const size_t start = bytes.size();
  bytes.resize(start + values.size() * sizeof(T));
  std::memcpy(bytes.data() + start, values.data(), values.size() * sizeof(T));
}

// Appends `values` to buffer 0 as a new bufferView (4-byte aligned, as accessors of floats need,
// glTF 2.0 section 3.6.2.4) and returns the view's index.
template <typename T>
int add_buffer_view(tinygltf::Model& model, const std::vector<T>& values, int target) {
  Bytes& data = model.buffers[0].data;
  data.resize((data.size() + 3) & ~size_t{3}, 0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = values.size() * sizeof(T);
  view.target = target;
  append_raw(data, values);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size()) - 1;
}

int add_accessor(tinygltf::Model& model, int buffer_view, int component_type, int type, size_t count) {
  tinygltf::Accessor accessor;
  accessor.bufferView = buffer_view;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size()) - 1;
}

// Adds the mesh with one primitive, a node showing it and the scene holding that node.
void add_mesh_node(tinygltf::Model& model, const MeshData& mesh, const std::string& name, int material) {
  if (model.buffers.empty()) model.buffers.emplace_back();
  const int positions = add_accessor(model, add_buffer_view(model, mesh.positions, TINYGLTF_TARGET_ARRAY_BUFFER),
                                     TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, mesh.positions.size());
  // POSITION accessors must carry min and max (glTF 2.0 spec, "Meshes").
  glm::vec3 low = mesh.positions.front(), high = mesh.positions.front();
  for (const glm::vec3& p : mesh.positions) low = glm::min(low, p), high = glm::max(high, p);
  model.accessors[static_cast<size_t>(positions)].minValues = {low.x, low.y, low.z};
  model.accessors[static_cast<size_t>(positions)].maxValues = {high.x, high.y, high.z};
  const int normals = add_accessor(model, add_buffer_view(model, mesh.normals, TINYGLTF_TARGET_ARRAY_BUFFER),
                                   TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, mesh.normals.size());
  const int texcoords = add_accessor(model, add_buffer_view(model, mesh.texcoords, TINYGLTF_TARGET_ARRAY_BUFFER),
                                     TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, mesh.texcoords.size());
  const int indices = add_accessor(model, add_buffer_view(model, mesh.indices, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                                   TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, mesh.indices.size());
  // The buffer's length is padded to 4 too, so a later append or GLB packing needs no realignment.
  Bytes& data = model.buffers[0].data;
  data.resize((data.size() + 3) & ~size_t{3}, 0);

  tinygltf::Primitive primitive;
  primitive.attributes = {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", texcoords}};
  primitive.indices = indices;
  primitive.material = material;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = name;
  gltf_mesh.primitives.push_back(primitive);
  model.meshes.push_back(gltf_mesh);

  tinygltf::Node node;
  node.name = name;
  node.mesh = static_cast<int>(model.meshes.size()) - 1;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(static_cast<int>(model.nodes.size()) - 1);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
}

tinygltf::Model new_spec_gloss_model() {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "gltf-pbr samples";
  // Used but not required: the core pbrMetallicRoughness fallback keeps the file loadable by viewers
  // without the (archived) extension, as legacy exporters did.
  model.extensionsUsed.push_back(kSpecGloss);
  return model;
}

tinygltf::Value number_array(std::initializer_list<double> values) {
  tinygltf::Value::Array array;
  for (const double v : values) array.emplace_back(v);
  return tinygltf::Value(std::move(array));
}

tinygltf::Value texture_info(int texture) {
  tinygltf::Value::Object info;
  info["index"] = tinygltf::Value(texture);
  return tinygltf::Value(std::move(info));
}

// A legacy material: the extension carries the real description; the core fallback is what
// legacy exporters wrote (base colour = diffuse, not metallic, roughness = 1 - glossiness), which
// turns every metal dark and which a converter must therefore replace.
tinygltf::Material spec_gloss_material(const std::string& name, const tinygltf::Value::Object& extension,
                                       glm::dvec4 fallback_base_color, double glossiness) {
  tinygltf::Material material;
  material.name = name;
  material.emissiveFactor = {0.0, 0.0, 0.0};  // tinygltf leaves it empty and would write "[]"
  material.pbrMetallicRoughness.baseColorFactor = {fallback_base_color.r, fallback_base_color.g,
                                                   fallback_base_color.b, fallback_base_color.a};
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 1.0 - glossiness;
  material.extensions[kSpecGloss] = tinygltf::Value(extension);
  return material;
}

// ---------------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------------

// Saves through the project's own writer, which names the external files <stem>.bin and
// <stem>_<image name>.png beside the .gltf, and returns every file name it wrote (relative to
// `folder`), the .gltf first.
std::vector<std::string> save_sample(tinygltf::Model model, const fs::path& folder, const std::string& stem) {
  gltf_pbr::Asset asset;
  // save_asset never overwrites the file an asset was loaded from. This asset was loaded from
  // nowhere: a name that is never written keeps that guard from matching any output.
  asset.path = folder / (stem + ".in-memory");
  asset.model = std::move(model);
  const std::string gltf_name = stem + ".gltf";
  gltf_pbr::save_asset(asset, folder / gltf_name);

  std::vector<std::string> written{gltf_name};
  if (asset.model.buffers.size() != 1) throw std::logic_error(stem + ": samples keep one buffer");
  written.push_back(stem + ".bin");
  for (const auto& image : asset.model.images) written.push_back(image.uri);  // save_asset set the URIs
  for (const auto& name : written)
    if (!fs::is_regular_file(folder / name))
      throw std::runtime_error("save_asset did not write the expected file " + (folder / name).string());
  return written;
}

std::vector<std::string> write_factor_sample(const FactorSample& sample, const fs::path& folder) {
  tinygltf::Model model = new_spec_gloss_model();
  tinygltf::Value::Object extension;
  extension["diffuseFactor"] =
      number_array({sample.diffuse.r, sample.diffuse.g, sample.diffuse.b, sample.diffuse.a});
  extension["specularFactor"] = number_array({sample.specular.r, sample.specular.g, sample.specular.b});
  extension["glossinessFactor"] = tinygltf::Value(sample.glossiness);
  model.materials.push_back(spec_gloss_material(sample.name, extension, sample.diffuse, sample.glossiness));

  // 32 x 16 keeps highlights round in a preview while each .bin stays ~24 KB.
  const MeshData sphere = make_uv_sphere(/*radius=*/1.0, /*segments=*/32, /*rings=*/16);
  check_outward_winding(sphere, "uv-sphere");
  add_mesh_node(model, sphere, sample.name, /*material=*/0);
  return save_sample(std::move(model), folder, sample.file_stem);
}

std::uint8_t to_byte(double unit) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(unit, 0.0, 1.0) * 255.0));
}
std::uint8_t to_srgb_byte(double linear) { return to_byte(gltf_pbr::linear_to_srgb(static_cast<float>(linear))); }

// The textured sample: a crate whose 64x64 maps are a 4x4 checker of painted plastic and bare iron.
// Both classes in one texture make the converter solve per texel (metalness 0 and 1 side by side,
// with filtered edges in between); alpha and glossiness ramps make each texel distinct, so a
// channel swap or a missed sRGB decode shows as a gradient in the wrong direction.
std::vector<std::string> write_textured_crate(const fs::path& folder) {
  constexpr int kSize = 64, kCell = 16;
  const glm::dvec3 paint_linear{0.45, 0.12, 0.03};  // an orange paint, inside the albedo range
  const glm::dvec3 paint_specular{0.04};            // DESIGN.md: plastic F0 0.04
  const glm::dvec3 iron_specular{0.562, 0.565, 0.578};  // DESIGN.md's F0 table, iron

  // Legacy texture encodings (DESIGN.md, "Conversion"): diffuse RGB sRGB and A linear;
  // specularGlossiness RGB sRGB and A (glossiness) linear.
  std::vector<std::uint8_t> diffuse(kSize * kSize * 4), specular_glossiness(kSize * kSize * 4);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const bool bare_metal = ((x / kCell) + (y / kCell)) % 2 == 1;
      const double across = x / double(kSize - 1), down = y / double(kSize - 1);
      const glm::dvec3 diffuse_linear = bare_metal ? glm::dvec3(0.0) : paint_linear;
      const glm::dvec3 specular = bare_metal ? iron_specular : paint_specular;
      // Paint is satin (0.35-0.6 down the texture); metal is worn to polished (0.55-0.9 across).
      const double glossiness = bare_metal ? 0.55 + 0.35 * across : 0.35 + 0.25 * down;
      const double alpha = 1.0 - 0.5 * down;  // opaque at the top, half transparent at the bottom

      const size_t texel = (static_cast<size_t>(y) * kSize + static_cast<size_t>(x)) * 4;
      for (int c = 0; c < 3; ++c) {
        diffuse[texel + static_cast<size_t>(c)] = to_srgb_byte(diffuse_linear[c]);
        specular_glossiness[texel + static_cast<size_t>(c)] = to_srgb_byte(specular[c]);
      }
      diffuse[texel + 3] = to_byte(alpha);
      specular_glossiness[texel + 3] = to_byte(glossiness);
    }
  }

  tinygltf::Model model = new_spec_gloss_model();
  auto add_png = [&](const std::string& name, const std::vector<std::uint8_t>& texels) {
    tinygltf::Image image;
    image.name = name;  // save_asset writes textured-crate_<name>.png
    image.mimeType = "image/png";
    image.width = kSize;
    image.height = kSize;
    image.component = 4;
    image.bits = 8;
    image.as_is = true;  // the bytes are encoded PNG, as load_asset keeps them
    image.image = gltf_pbr::encode_png(texels, kSize, kSize, 4, /*compression_level=*/9);
    model.images.push_back(image);
    tinygltf::Texture texture;
    texture.source = static_cast<int>(model.images.size()) - 1;
    texture.sampler = 0;
    model.textures.push_back(texture);
    return static_cast<int>(model.textures.size()) - 1;
  };
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  model.samplers.push_back(sampler);
  const int diffuse_texture = add_png("diffuse", diffuse);
  const int spec_gloss_texture = add_png("specularGlossiness", specular_glossiness);

  // Factors stay at their defaults (1), so the textures alone define the material.
  tinygltf::Value::Object extension;
  extension["diffuseTexture"] = texture_info(diffuse_texture);
  extension["specularGlossinessTexture"] = texture_info(spec_gloss_texture);
  tinygltf::Material material = spec_gloss_material("painted-crate", extension, glm::dvec4(1.0), /*glossiness=*/0.5);
  material.pbrMetallicRoughness.baseColorTexture.index = diffuse_texture;
  material.alphaMode = "BLEND";  // the diffuse alpha ramp is meant to be seen and kept
  model.materials.push_back(material);

  const MeshData cube = make_cube(/*half_extent=*/0.5f);
  check_outward_winding(cube, "crate");
  add_mesh_node(model, cube, "crate", /*material=*/0);
  return save_sample(std::move(model), folder, "textured-crate");
}

void write_index(const fs::path& folder, const std::vector<std::string>& written) {
  std::string text;
  for (const auto& name : written) text += name + "\n";
  gltf_pbr::AtomicWriteSet files;
  files.stage(folder / "index.txt", Bytes(text.begin(), text.end()));
  files.commit();
}

int run(const fs::path& folder) {
  fs::create_directories(folder);
  std::vector<std::string> written;
  for (const FactorSample& sample : kFactorSamples) {
    const auto files = write_factor_sample(sample, folder);
    written.insert(written.end(), files.begin(), files.end());
  }
  const auto crate_files = write_textured_crate(folder);
  written.insert(written.end(), crate_files.begin(), crate_files.end());
  // Last, so that the build's dependency on index.txt means every sample exists.
  write_index(folder, written);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_FOLDER\n", argc > 0 ? argv[0] : "generate-samples");
    return 2;
  }
  try {
    return run(argv[1]);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "generate-samples: %s\n", error.what());
    return 1;
  }
}
