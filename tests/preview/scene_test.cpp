// Material inputs through the G-buffer: texture sets and transforms, mip selection, vertex
// colours, normal maps, alpha modes, and environments read from .hdr files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "core/files.hpp"
#include "core/image.hpp"
#include "preview/preview.hpp"

namespace gltf_pbr::preview {
namespace {

Texture two_by_two(std::initializer_list<std::uint8_t> rgba) {
  Texture t;
  t.width = t.height = 2;
  t.rgba = rgba;
  t.build_mips();
  return t;
}

TEST(Texture, SecondUvSetAndTextureTransformPickTheRightTexel) {
  const Texture texture = two_by_two({255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255});
  TextureSlot slot;
  slot.texture = &texture;
  slot.nearest = true;
  slot.tex_coord = 1;
  const glm::vec2 uv[2] = {{0.75f, 0.75f}, {0.25f, 0.25f}};
  EXPECT_EQ(sample(slot, uv), glm::vec4(1, 0, 0, 1));  // set 1 -> texel (0, 0)
  // KHR_texture_transform offset (0.5, 0): texel (1, 0).
  slot.has_transform = true;
  slot.row_u = glm::vec3(1, 0, 0.5f);
  slot.row_v = glm::vec3(0, 1, 0);
  EXPECT_EQ(sample(slot, uv), glm::vec4(0, 1, 0, 1));
  // Rotation by 90 degrees (u' = v, v' = -u), offset (0, 1): (0.25, 0.25) -> (0.25, 0.75) -> texel (0, 1).
  slot.row_u = glm::vec3(0, 1, 0);
  slot.row_v = glm::vec3(-1, 0, 1);
  EXPECT_EQ(sample(slot, uv), glm::vec4(0, 0, 1, 1));
}

TEST(Texture, MinifiedCheckerboardAveragesToGrey) {
  Texture checker;
  checker.width = checker.height = 64;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 4; ++c) checker.rgba.push_back(c == 3 ? 255 : ((x + y) % 2 ? 255 : 0));
  checker.build_mips();
  TextureSlot slot;
  slot.texture = &checker;
  const glm::vec2 uv[2] = {{0.3f, 0.6f}, {}};
  UvDerivatives far_away;
  far_away.dx[0] = glm::vec2(0.5f, 0.0f);  // half the texture per pixel
  far_away.dy[0] = glm::vec2(0.0f, 0.5f);
  EXPECT_NEAR(sample(slot, uv, &far_away).x, 0.5f, 0.02f);
  const glm::vec2 texel_centre[2] = {{18.5f / 64.0f, 38.5f / 64.0f}, {}};
  const float magnified = sample(slot, texel_centre).x;  // level 0, one texel
  EXPECT_TRUE(magnified < 0.3f || magnified > 0.7f);
}

// A 2 x 2 quad facing +Z in front of a camera at z = 3, one material.
struct QuadScene {
  Scene scene;
  Texture texture;
  explicit QuadScene(PreviewMaterial material, glm::vec4 vertex_color = glm::vec4(1.0f), glm::vec4 tangent = {}) {
    scene.materials = {std::move(material), PreviewMaterial{}};
    const glm::vec3 corners[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    for (int i = 0; i < 4; ++i) {
      Vertex v;
      v.position = corners[i];
      v.normal = glm::vec3(0, 0, 1);
      v.tangent = tangent;
      v.uv[0] = glm::vec2(corners[i].x * 0.5f + 0.5f, 0.5f - corners[i].y * 0.5f);
      v.color = vertex_color;
      scene.vertices.push_back(v);
      scene.bounds.add(glm::dvec3(corners[i]));
    }
    scene.triangles = {{{0, 1, 2}, 0}, {{0, 2, 3}, 0}};
  }
  GBuffers draw(int size = 64) {
    Camera camera;
    camera.eye = glm::dvec3(0, 0, 3);
    camera.tan_half_fov_y = 0.3;  // the quad overfills the view
    camera.near = 0.1;
    return fill_gbuffers(scene, rasterize(scene, camera, size, size), camera);
  }
};

TEST(GBufferResolve, VertexColourMultipliesBaseAndDiffuse) {
  PreviewMaterial m;
  m.base_color_factor = glm::vec4(1.0f, 1.0f, 1.0f, 1.0f);
  m.metallic_factor = 0.0f;
  m.has_spec_gloss = true;
  m.specular_factor = glm::vec3(0.04f);
  QuadScene quad(m, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
  const GBuffers g = quad.draw();
  const size_t centre = 32 * 64 + 32;
  const GBufferTexel after = read_after(g.after, centre), before = read_before(g.before, centre);
  ASSERT_TRUE(after.covered);
  EXPECT_NEAR(after.color_a.x, 1.0f, 0.01f);
  EXPECT_NEAR(after.color_a.y, 0.0f, 0.01f);
  EXPECT_NEAR(before.color_a.x, 1.0f, 0.01f);
  EXPECT_NEAR(before.color_a.z, 0.0f, 0.01f);
}

TEST(GBufferResolve, NormalMapTiltsTheNormalInTheTangentFrame) {
  // Texel (0.5 + 0.5 sin 30deg, 0.5, 0.5 + 0.5 cos 30deg): the normal leans 30 degrees towards +T = +X.
  PreviewMaterial m;
  QuadScene quad(m, glm::vec4(1.0f), glm::vec4(1, 0, 0, 1));
  quad.texture = two_by_two({191, 128, 238, 255, 191, 128, 238, 255, 191, 128, 238, 255, 191, 128, 238, 255});
  quad.scene.materials[0].normal_texture.texture = &quad.texture;
  const GBuffers g = quad.draw();
  const glm::vec3 n = read_after(g.after, 32 * 64 + 32).normal;
  EXPECT_NEAR(n.x, 0.5f, 0.02f);
  EXPECT_NEAR(n.y, 0.0f, 0.02f);
  EXPECT_NEAR(n.z, 0.866f, 0.02f);
}

TEST(GBufferResolve, NormalMapPointingBehindTheSurfaceShadesFinite) {
  PreviewMaterial m;
  QuadScene quad(m, glm::vec4(1.0f), glm::vec4(1, 0, 0, 1));
  quad.texture = two_by_two({255, 128, 0, 255, 255, 128, 0, 255, 255, 128, 0, 255, 255, 128, 0, 255});  // z = -1
  quad.scene.materials[0].normal_texture.texture = &quad.texture;
  const GBuffers g = quad.draw();
  Camera camera;
  camera.eye = glm::dvec3(0, 0, 3);
  camera.tan_half_fov_y = 0.3;
  const LitPair lit = light_both(g, default_environment(), camera, LightingOptions{}, /*keep_radiance=*/true);
  ASSERT_FALSE(lit.after_hdr.radiance.empty());
  for (const auto& c : lit.after_hdr.radiance) ASSERT_TRUE(std::isfinite(c.x + c.y + c.z));
  for (const auto& c : lit.before_hdr.radiance) ASSERT_TRUE(std::isfinite(c.x + c.y + c.z));
}

TEST(GBufferResolve, AlphaMaskCutsAndBlendDithersCoverage) {
  auto coverage = [](AlphaMode mode, float alpha) {
    PreviewMaterial m;
    m.alpha_mode = mode;
    m.base_color_factor = glm::vec4(1, 1, 1, alpha);
    QuadScene quad(m);
    const GBuffers g = quad.draw();
    long covered = 0;
    for (float d : g.after.depth) covered += std::isfinite(d);
    return static_cast<double>(covered) / static_cast<double>(g.after.depth.size());
  };
  EXPECT_EQ(coverage(AlphaMode::Opaque, 0.2f), 1.0);
  EXPECT_EQ(coverage(AlphaMode::Mask, 0.4f), 0.0);  // below alphaCutoff 0.5
  EXPECT_EQ(coverage(AlphaMode::Mask, 0.6f), 1.0);
  EXPECT_NEAR(coverage(AlphaMode::Blend, 0.5f), 0.5, 0.02);
  EXPECT_NEAR(coverage(AlphaMode::Blend, 0.25f), 0.25, 0.02);
}

TEST(Environment, RadianceHdrFileLightsTheFurnace) {
  // A flat (not run-length encoded) Radiance file of constant radiance 1: RGBE (128, 128, 128, 129).
  const fs::path path = fs::temp_directory_path() / "gltf-pbr-preview-furnace.hdr";
  std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 16\n";
  Bytes bytes(header.begin(), header.end());
  for (int i = 0; i < 8 * 16; ++i) bytes.insert(bytes.end(), {128, 128, 128, 129});
  {
    AtomicWriteSet files;
    files.stage(path, bytes);
    files.commit();
  }
  const Environment env = load_environment(path);
  fs::remove(path);
  EXPECT_NEAR(env.prefiltered_radiance(glm::vec3(0, 1, 0), 0.5f).x, 1.0f, 0.01f);  // (128.5/256) * 2
  LightingOptions options;
  options.sun = false;
  const glm::vec3 c = shade_point(metal_rough_lobes(glm::vec3(1.0f), 0.0f, 0.5f), 0.5f, glm::vec3(0, 0, 1),
                                  glm::normalize(glm::vec3(0.3f, 0, 1)), 1.0f, glm::vec3(0.0f), env, options);
  EXPECT_NEAR(c.x, 1.0f, 0.01f);
}

TEST(Environment, AnHdrHeaderClaimingMoreThanTheLimitOrItsBytesIsRefusedBeforeAllocating) {
  const auto read = [](const std::string& resolution, std::size_t pixel_bytes) {
    std::string header = "#?RADIANCE\n\n" + resolution + "\n";
    std::vector<std::uint8_t> bytes(header.begin(), header.end());
    bytes.resize(bytes.size() + pixel_bytes, 128);
    try {
      (void)read_radiance_hdr(bytes, "claim.hdr");
      return std::string("read");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
  };
  // 30000 x 30000 in 100 bytes: above the default limit of 16384^2.
  EXPECT_NE(read("-Y 30000 +X 30000", 100).find("above the limit"), std::string::npos);
  // 4000 x 4000 fits the limit, but its 4000 scanlines need at least 4 + 8 * 32 bytes each.
  EXPECT_NE(read("-Y 4000 +X 4000", 1000).find("truncated pixel data"), std::string::npos);
  EXPECT_NE(read("-Y 100000 +X 100000", 0).find("above the limit"), std::string::npos);
  EXPECT_NE(read("+Y 8 +X 8", 256).find("'+Y 8 +X 8'"), std::string::npos);  // the line it could not use
  EXPECT_EQ(read("-Y 2 +X 2", 16), "read");
}

TEST(Environment, RunLengthEncodedHdrDecodes) {
  // One scanline of width 8, new-style RLE: each channel a run of 8 (count 128 + 8).
  std::string header = "#?RADIANCE\n\n-Y 1 +X 8\n";
  std::vector<std::uint8_t> bytes(header.begin(), header.end());
  bytes.insert(bytes.end(), {2, 2, 0, 8, 136, 64, 136, 128, 136, 255, 136, 130});
  const EquirectMap map = read_radiance_hdr(bytes, "rle.hdr");
  ASSERT_EQ(map.width, 8);
  EXPECT_NEAR(map.at(3, 0).x, (64.5f / 256.0f) * 4.0f, 1e-5f);
  EXPECT_NEAR(map.at(7, 0).z, (255.5f / 256.0f) * 4.0f, 1e-5f);
  EXPECT_THROW(read_radiance_hdr(std::vector<std::uint8_t>(header.begin(), header.end()), "cut.hdr"),
               std::runtime_error);
}

}  // namespace
}  // namespace gltf_pbr::preview

namespace gltf_pbr::preview {
namespace {

// One triangle with TEXCOORD_1 and COLOR_0 as normalized integers, a 2 x 2 PNG base colour read
// through texCoord 1 and KHR_texture_transform, under a mirroring node transform.
Asset attribute_asset() {
  Asset asset;
  asset.path = "attributes.gltf";
  tinygltf::Model& m = asset.model;
  tinygltf::Buffer buffer;
  auto append = [&](const void* data, size_t bytes) {
    while (buffer.data.size() % 4) buffer.data.push_back(0);
    const size_t offset = buffer.data.size();
    buffer.data.resize(offset + bytes);
    std::memcpy(buffer.data.data() + offset, data, bytes);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = bytes;
    m.bufferViews.push_back(view);
    return static_cast<int>(m.bufferViews.size() - 1);
  };
  auto accessor = [&](int view, int component, int type, size_t count, bool normalized) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.type = type;
    a.count = count;
    a.normalized = normalized;
    m.accessors.push_back(a);
    return static_cast<int>(m.accessors.size() - 1);
  };
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t uv1[] = {0, 0, 65535, 0, 0, 32768};
  const std::uint8_t colors[] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 128};
  const std::vector<std::uint8_t> texels = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
  const Bytes png = encode_png(texels, 2, 2, 3, 6);
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] =
      accessor(append(positions, sizeof positions), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3, false);
  primitive.attributes["TEXCOORD_1"] =
      accessor(append(uv1, sizeof uv1), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC2, 3, true);
  primitive.attributes["COLOR_0"] =
      accessor(append(colors, sizeof colors), TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, 3, true);
  primitive.material = 0;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Image image;
  image.bufferView = append(png.data(), png.size());
  image.mimeType = "image/png";
  m.images.push_back(image);
  m.buffers.push_back(buffer);
  tinygltf::Texture texture;
  texture.source = 0;
  m.textures.push_back(texture);
  tinygltf::Material material;
  material.pbrMetallicRoughness.baseColorTexture.index = 0;
  material.pbrMetallicRoughness.baseColorTexture.texCoord = 0;  // overridden by the transform's texCoord
  tinygltf::Value::Object transform;
  transform["offset"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(0.5), tinygltf::Value(0.0)});
  transform["texCoord"] = tinygltf::Value(1);
  material.pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] = tinygltf::Value(transform);
  m.materials.push_back(material);
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(primitive);
  m.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.scale = {-2.0, 2.0, 2.0};  // mirrored: the winding must flip to stay front-facing
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  return asset;
}

TEST(SceneBuild, ReadsNormalizedAttributesTextureSetsAndTransforms) {
  const Asset asset = attribute_asset();
  const Scene scene = build_scene(asset, asset);
  ASSERT_EQ(scene.triangles.size(), 1u);
  ASSERT_EQ(scene.vertices.size(), 3u);
  EXPECT_EQ(scene.vertices[1].position, glm::vec3(-2, 0, 0));
  EXPECT_NEAR(scene.vertices[1].uv[1].x, 1.0f, 1e-6f);
  EXPECT_NEAR(scene.vertices[2].uv[1].y, 32768.0f / 65535.0f, 1e-6f);
  EXPECT_NEAR(scene.vertices[2].color.w, 128.0f / 255.0f, 1e-6f);
  EXPECT_EQ(scene.vertices[1].color, glm::vec4(0, 1, 0, 1));
  // Mirrored node: vertices 1 and 2 swap so that the face stays counter-clockwise from +Z.
  EXPECT_EQ(scene.triangles[0].vertex[1], 2u);
  const PreviewMaterial& material = scene.materials[0];
  ASSERT_TRUE(material.base_color_texture);
  EXPECT_EQ(material.base_color_texture.tex_coord, 1);
  EXPECT_TRUE(material.base_color_texture.has_transform);
  EXPECT_EQ(scene.stats.textures_decoded, 1);
  // uv1 (0, 0) + offset (0.5, 0): the texel at (1, 0), green.
  const glm::vec2 uv[2] = {{0.9f, 0.9f}, {0.0f + 0.25f, 0.25f}};
  const glm::vec4 texel = sample(material.base_color_texture, uv);
  EXPECT_NEAR(texel.y, 1.0f, 1e-3f);
  EXPECT_NEAR(texel.x, 0.0f, 1e-3f);
}

}  // namespace
}  // namespace gltf_pbr::preview
