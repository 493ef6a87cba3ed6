// core/meshopt and the Asset's reading of EXT_meshopt_compression views: what meshoptimizer's
// encoder writes decodes back; layouts the extension forbids and hostile byte counts are refused
// before anything is allocated; an Asset decodes a view once, on first read; saving (.gltf, .glb)
// and pruning keep the compressed bytes as they were and the fallback buffer without data.
#include "core/meshopt.hpp"

#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>

#include "core/accessor.hpp"
#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/json.hpp"
#include "tests/test_support.hpp"

namespace gltf_pbr {
namespace {

Bytes encode_attributes(const void* elements, std::size_t count, std::size_t stride) {
  Bytes out(meshopt_encodeVertexBufferBound(count, stride));
  out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), elements, count, stride));
  return out;
}

Bytes encode_triangles(const std::vector<std::uint32_t>& indices, std::size_t vertices) {
  Bytes out(meshopt_encodeIndexBufferBound(indices.size(), vertices));
  out.resize(meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), indices.size()));
  return out;
}

MeshoptView layout(std::uint64_t stride, std::uint64_t count, MeshoptMode mode,
                   MeshoptFilter filter = MeshoptFilter::None) {
  MeshoptView view;
  view.byte_stride = stride;
  view.count = count;
  view.mode = mode;
  view.filter = filter;
  return view;
}

std::vector<float> random_floats(std::size_t n, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> uniform(-100.0f, 100.0f);
  std::vector<float> out(n);
  for (float& value : out) value = uniform(random);
  return out;
}

TEST(Meshopt, AttributesDecodeToTheBytesThatWereEncoded) {
  const std::vector<float> positions = random_floats(3 * 1000, 1);
  const Bytes compressed = encode_attributes(positions.data(), 1000, 12);
  std::string problem;
  const auto decoded = decode_meshopt(compressed, layout(12, 1000, MeshoptMode::Attributes), problem);
  ASSERT_TRUE(decoded) << problem;
  ASSERT_EQ(decoded->size(), positions.size() * 4);
  EXPECT_EQ(std::memcmp(decoded->data(), positions.data(), decoded->size()), 0);
}

TEST(Meshopt, TrianglesDecodeToTheSameTrianglesWithTheirWinding) {
  std::vector<std::uint32_t> indices;
  for (std::uint32_t row = 0; row < 20; ++row)
    for (std::uint32_t column = 0; column < 20; ++column) {
      const std::uint32_t corner = row * 21 + column;
      indices.insert(indices.end(), {corner, corner + 1, corner + 21, corner + 1, corner + 22, corner + 21});
    }
  const Bytes compressed = encode_triangles(indices, 21 * 21);
  for (const std::uint64_t stride : {2u, 4u}) {
    std::string problem;
    const auto decoded = decode_meshopt(compressed, layout(stride, indices.size(), MeshoptMode::Triangles), problem);
    ASSERT_TRUE(decoded) << problem;
    // The codec may rotate a triangle's corners; winding and triangle order stay.
    for (std::size_t t = 0; t < indices.size() / 3; ++t) {
      std::array<std::uint32_t, 3> got{};
      for (int k = 0; k < 3; ++k) {
        std::uint32_t value = 0;
        std::memcpy(&value, decoded->data() + (t * 3 + k) * stride, stride);
        got[k] = value;
      }
      const std::array<std::uint32_t, 3> want{indices[t * 3], indices[t * 3 + 1], indices[t * 3 + 2]};
      const bool rotated = got == want || got == std::array{want[1], want[2], want[0]} ||
                           got == std::array{want[2], want[0], want[1]};
      ASSERT_TRUE(rotated) << "triangle " << t << " at stride " << stride;
    }
  }
}

TEST(Meshopt, IndexSequencesDecodeExactly) {
  std::vector<std::uint32_t> sequence(500);
  std::iota(sequence.begin(), sequence.end(), 7);
  Bytes compressed(meshopt_encodeIndexSequenceBound(sequence.size(), 600));
  compressed.resize(meshopt_encodeIndexSequence(compressed.data(), compressed.size(), sequence.data(), sequence.size()));
  std::string problem;
  const auto decoded = decode_meshopt(compressed, layout(4, sequence.size(), MeshoptMode::Indices), problem);
  ASSERT_TRUE(decoded) << problem;
  EXPECT_EQ(std::memcmp(decoded->data(), sequence.data(), decoded->size()), 0);
}

TEST(Meshopt, FiltersGiveBackUnitVectorsQuaternionsAndFloatsWithinTheirPrecision) {
  const std::size_t count = 256;
  std::vector<float> unit(count * 4), quaternions(count * 4);
  std::mt19937 random(3);
  std::normal_distribution<float> normal;
  for (std::size_t i = 0; i < count; ++i) {
    float length = 0, q_length = 0;
    for (int c = 0; c < 4; ++c) {
      unit[i * 4 + c] = c < 3 ? normal(random) : 0.0f;
      quaternions[i * 4 + c] = normal(random);
      length += unit[i * 4 + c] * unit[i * 4 + c];
      q_length += quaternions[i * 4 + c] * quaternions[i * 4 + c];
    }
    for (int c = 0; c < 4; ++c) {
      unit[i * 4 + c] /= std::sqrt(length);
      quaternions[i * 4 + c] /= std::sqrt(q_length);
    }
  }
  const std::vector<float> floats = random_floats(count * 3, 4);
  struct Case {
    MeshoptFilter filter;
    std::size_t stride;
    const std::vector<float>* values;
    int components;
    double tolerance;
  };
  for (const Case& c : {Case{MeshoptFilter::Octahedral, 8, &unit, 3, 1e-3},
                        Case{MeshoptFilter::Quaternion, 8, &quaternions, 4, 1e-3},
                        Case{MeshoptFilter::Exponential, 12, &floats, 3, 1e-3}}) {
    Bytes filtered(count * c.stride);
    if (c.filter == MeshoptFilter::Octahedral)
      meshopt_encodeFilterOct(filtered.data(), count, c.stride, 16, c.values->data());
    else if (c.filter == MeshoptFilter::Quaternion)
      meshopt_encodeFilterQuat(filtered.data(), count, c.stride, 16, c.values->data());
    else
      meshopt_encodeFilterExp(filtered.data(), count, c.stride, 23, c.values->data());
    const Bytes compressed = encode_attributes(filtered.data(), count, c.stride);
    std::string problem;
    const auto decoded = decode_meshopt(compressed, layout(c.stride, count, MeshoptMode::Attributes, c.filter), problem);
    ASSERT_TRUE(decoded) << problem;
    const std::size_t source_components = c.values == &floats ? 3 : 4;
    for (std::size_t i = 0; i < count; ++i) {
      std::array<double, 4> got{}, want{};
      double dot = 0;
      for (int k = 0; k < c.components; ++k) {
        const std::uint8_t* at = decoded->data() + i * c.stride;
        if (c.filter == MeshoptFilter::Exponential) {
          float value = 0;
          std::memcpy(&value, at + static_cast<std::size_t>(k) * 4, 4);
          got[k] = value;
        } else {
          std::int16_t value = 0;
          std::memcpy(&value, at + static_cast<std::size_t>(k) * 2, 2);
          got[k] = value / 32767.0;  // 16-bit normalized (the extension's Appendix B)
        }
        want[k] = (*c.values)[i * source_components + static_cast<std::size_t>(k)];
        dot += got[k] * want[k];
      }
      // A quaternion and its negation are one rotation: the filter may give either.
      const double sign = c.filter == MeshoptFilter::Quaternion && dot < 0 ? -1 : 1;
      for (int k = 0; k < c.components; ++k)
        ASSERT_NEAR(sign * got[k], want[k], c.tolerance * std::max(1.0, std::fabs(want[k])))
            << "filter " << static_cast<int>(c.filter) << " element " << i << " component " << k;
    }
  }
}

TEST(Meshopt, LayoutsTheExtensionForbidsAreNamed) {
  struct Case {
    MeshoptView view;
    std::uint64_t parent_length, parent_stride;
    const char* says;
  };
  const Case cases[] = {
      {layout(12, 10, MeshoptMode::Attributes), 120, 16, "differs from the extension's 12"},
      {layout(12, 10, MeshoptMode::Attributes), 124, 0, "is not byteStride 12 times count 10"},
      {layout(6, 10, MeshoptMode::Attributes), 60, 0, "divisible by 4 and at most 256"},
      {layout(260, 1, MeshoptMode::Attributes), 260, 0, "divisible by 4 and at most 256"},
      {layout(2, 10, MeshoptMode::Triangles), 20, 0, "count divisible by 3"},
      {layout(8, 3, MeshoptMode::Triangles), 24, 0, "byteStride of 2 or 4"},
      {layout(4, 3, MeshoptMode::Indices, MeshoptFilter::Octahedral), 12, 0, "take no filter"},
      {layout(12, 2, MeshoptMode::Attributes, MeshoptFilter::Octahedral), 24, 0, "OCTAHEDRAL needs"},
      {layout(4, 2, MeshoptMode::Attributes, MeshoptFilter::Quaternion), 8, 0, "QUATERNION needs"},
  };
  for (const Case& c : cases) {
    const std::string problem = meshopt_layout_problem(c.view, c.parent_length, c.parent_stride);
    EXPECT_NE(problem.find(c.says), std::string::npos) << "got: " << problem;
  }
  // Near misses: each rule's smallest valid neighbour.
  EXPECT_EQ(meshopt_layout_problem(layout(12, 10, MeshoptMode::Attributes), 120, 12), "");
  EXPECT_EQ(meshopt_layout_problem(layout(256, 1, MeshoptMode::Attributes, MeshoptFilter::Exponential), 256, 0), "");
  EXPECT_EQ(meshopt_layout_problem(layout(2, 9, MeshoptMode::Triangles), 18, 0), "");
  EXPECT_EQ(meshopt_layout_problem(layout(4, 3, MeshoptMode::Attributes, MeshoptFilter::Octahedral), 12, 0), "");
}

// A JSON value as tinygltf 2.7 holds it (ParseJsonAsValue, static in its header): integers as
// int, other numbers as double. Integers beyond an int are refused by the loader before tinygltf
// reads them (MeshoptAsset.ExtensionIntegersTheDocumentLibraryCannotHoldAreRefusedWithTheirPointer).
tinygltf::Value value_as_tinygltf_reads_it(const nlohmann::json& json) {
  switch (json.type()) {
    case nlohmann::json::value_t::object: {
      tinygltf::Value::Object object;
      for (const auto& [key, member] : json.items()) object[key] = value_as_tinygltf_reads_it(member);
      return tinygltf::Value(std::move(object));
    }
    case nlohmann::json::value_t::array: {
      tinygltf::Value::Array array;
      for (const auto& element : json) array.push_back(value_as_tinygltf_reads_it(element));
      return tinygltf::Value(std::move(array));
    }
    case nlohmann::json::value_t::string:
      return tinygltf::Value(json.get<std::string>());
    case nlohmann::json::value_t::boolean:
      return tinygltf::Value(json.get<bool>());
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
      return tinygltf::Value(static_cast<int>(json.get<std::int64_t>()));
    case nlohmann::json::value_t::number_float:
      return tinygltf::Value(json.get<double>());
    default:
      return tinygltf::Value();
  }
}

// One reader of the extension object for both documents: tinygltf's values (what convert,
// preview and the mesh checks read) and our JSON tree (the loader's pre-pass, the structure step)
// give the same view, or the same reason there is none.
TEST(Meshopt, TheExtensionObjectReadsTheSameInBothDocuments) {
  const char* objects[] = {
      R"({"buffer": 1, "byteOffset": 8, "byteLength": 40, "byteStride": 12, "count": 10, "mode": "ATTRIBUTES"})",
      R"({"buffer": 0, "byteLength": 9, "byteStride": 2, "count": 9, "mode": "TRIANGLES", "filter": "NONE"})",
      R"({"buffer": 0, "byteLength": 9, "byteStride": 4, "count": 2, "mode": "ATTRIBUTES", "filter": "OCTAHEDRAL"})",
      R"({"buffer": 0, "byteLength": 9, "byteStride": 4, "count": 2, "mode": "INDICES", "filter": "NEAREST"})",
      R"({"buffer": 0, "byteLength": 9, "byteStride": 4, "count": 2, "mode": "POINTS"})",
      R"({"buffer": 0, "byteLength": 9, "byteStride": 4, "count": 2})",
      R"({"buffer": 0, "byteLength": 9, "byteStride": 4, "count": 2.5, "mode": "INDICES"})",
      R"({"buffer": -1, "byteLength": 9, "byteStride": 4, "count": 2, "mode": "INDICES"})",
      R"({"buffer": 0, "byteOffset": "8", "byteLength": 9, "byteStride": 4, "count": 2, "mode": "INDICES"})",
      R"({"byteLength": 9, "byteStride": 4, "count": 2, "mode": "INDICES"})",
      R"([1, 2])",
  };
  for (const char* object : objects) {
    SCOPED_TRACE(object);
    JsonDocument tree;
    const std::string text(object);
    ASSERT_FALSE(read_json(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), tree));
    tinygltf::BufferView view;
    view.extensions["EXT_meshopt_compression"] = value_as_tinygltf_reads_it(nlohmann::json::parse(text));
    std::string from_tree, from_tinygltf;
    const std::optional<MeshoptView> a = meshopt_view_from_json(tree, from_tree);
    const std::optional<MeshoptView> b = meshopt_view(view, from_tinygltf);
    EXPECT_EQ(from_tree, from_tinygltf);
    ASSERT_EQ(a.has_value(), b.has_value());
    EXPECT_EQ(a.has_value(), from_tree.empty());
    if (!a) continue;
    EXPECT_EQ(a->buffer, b->buffer);
    EXPECT_EQ(a->byte_offset, b->byte_offset);
    EXPECT_EQ(a->byte_length, b->byte_length);
    EXPECT_EQ(a->byte_stride, b->byte_stride);
    EXPECT_EQ(a->count, b->count);
    EXPECT_EQ(a->mode, b->mode);
    EXPECT_EQ(a->filter, b->filter);
  }
  // Integers as the structure step's schema reads them (core/json.hpp integer_value): 4.0 is 4, and
  // what lies beyond an int64 saturates, so a view too long or an index too large is still named.
  const std::string huge =
      R"({"buffer": 4294967296, "byteOffset": 1e20, "byteLength": 18446744073709551615, "byteStride": 4.0,)"
      R"( "count": 2, "mode": "ATTRIBUTES"})";
  JsonDocument tree;
  ASSERT_FALSE(read_json(std::span(reinterpret_cast<const std::uint8_t*>(huge.data()), huge.size()), tree));
  std::string problem;
  const std::optional<MeshoptView> view = meshopt_view_from_json(tree, problem);
  ASSERT_TRUE(view) << problem;
  EXPECT_EQ(view->buffer, 4294967296);
  EXPECT_EQ(view->byte_offset, static_cast<std::uint64_t>(INT64_MAX));
  EXPECT_EQ(view->byte_length, static_cast<std::uint64_t>(INT64_MAX));
  EXPECT_EQ(view->byte_stride, 4u);
}

TEST(Meshopt, HostileCountsAndBytesAreRefusedWithAReason) {
  const std::vector<float> values = random_floats(3 * 64, 5);
  const Bytes compressed = encode_attributes(values.data(), 64, 12);
  std::string problem;
  // 2^40 elements from a few hundred bytes: refused before the output is allocated.
  EXPECT_FALSE(decode_meshopt(compressed, layout(12, std::uint64_t{1} << 40, MeshoptMode::Attributes), problem));
  EXPECT_NE(problem.find("cannot hold"), std::string::npos) << problem;
  EXPECT_FALSE(decode_meshopt(compressed, layout(std::uint64_t{1} << 62, 16, MeshoptMode::Attributes), problem));
  EXPECT_FALSE(problem.empty());
  Bytes truncated(compressed.begin(), compressed.end() - 40);
  EXPECT_FALSE(decode_meshopt(truncated, layout(12, 64, MeshoptMode::Attributes), problem));
  EXPECT_NE(problem.find("end before"), std::string::npos) << problem;
  Bytes other_header = compressed;
  other_header[0] = 0xb0;
  EXPECT_FALSE(decode_meshopt(other_header, layout(12, 64, MeshoptMode::Attributes), problem));
  EXPECT_NE(problem.find("codec header"), std::string::npos) << problem;
  Bytes longer = compressed;
  longer.insert(longer.end() - 32, 64, std::uint8_t{0});
  EXPECT_FALSE(decode_meshopt(longer, layout(12, 64, MeshoptMode::Attributes), problem));
  EXPECT_FALSE(problem.empty());
  // Random bytes of every small length never crash the decoder.
  std::mt19937 random(6);
  for (std::size_t length = 0; length < 300; ++length) {
    Bytes noise(length);
    for (auto& byte : noise) byte = static_cast<std::uint8_t>(random());
    if (!noise.empty()) noise[0] = 0xa0;
    decode_meshopt(noise, layout(12, 16, MeshoptMode::Attributes), problem);
    decode_meshopt(noise, layout(2, 12, MeshoptMode::Triangles), problem);
    decode_meshopt(noise, layout(4, 12, MeshoptMode::Indices), problem);
  }
}

// An asset whose positions (accessor 0) and triangle indices (accessor 1) are compressed in
// buffer 0 behind `image_bytes` held by an image's view; buffer 1 is the fallback placeholder.
Asset compressed_asset(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices,
                       std::size_t image_bytes) {
  Asset asset;
  tinygltf::Model& model = asset.model;
  model.asset.version = "2.0";
  model.extensionsUsed = {"EXT_meshopt_compression"};
  model.extensionsRequired = {"EXT_meshopt_compression"};
  model.buffers.resize(2);
  Bytes& data = model.buffers[0].data;
  data.assign(image_bytes, 0x5a);
  tinygltf::Value::Object fallback{{"fallback", tinygltf::Value(true)}};
  model.buffers[1].extensions["EXT_meshopt_compression"] = tinygltf::Value(fallback);
  if (image_bytes > 0) {
    tinygltf::BufferView image_view;
    image_view.buffer = 0;
    image_view.byteLength = image_bytes;
    model.bufferViews.push_back(image_view);
    tinygltf::Image image;
    image.bufferView = 0;
    image.mimeType = "image/png";
    model.images.push_back(image);
  }
  auto add_view = [&](const Bytes& compressed, std::size_t stride, std::size_t count, const char* mode,
                      std::size_t& fallback_offset) {
    data.resize((data.size() + 3) & ~std::size_t{3}, 0);
    tinygltf::Value::Object extension{{"buffer", tinygltf::Value(0)},
                                      {"byteOffset", tinygltf::Value(static_cast<int>(data.size()))},
                                      {"byteLength", tinygltf::Value(static_cast<int>(compressed.size()))},
                                      {"byteStride", tinygltf::Value(static_cast<int>(stride))},
                                      {"count", tinygltf::Value(static_cast<int>(count))},
                                      {"mode", tinygltf::Value(std::string(mode))}};
    data.insert(data.end(), compressed.begin(), compressed.end());
    tinygltf::BufferView view;
    view.buffer = 1;
    view.byteOffset = fallback_offset;
    view.byteLength = stride * count;
    view.extensions["EXT_meshopt_compression"] = tinygltf::Value(extension);
    fallback_offset += (view.byteLength + 3) & ~std::size_t{3};
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size()) - 1;
  };
  std::size_t fallback_offset = 0;
  std::vector<std::uint16_t> short_indices(indices.begin(), indices.end());
  tinygltf::Accessor position;
  position.bufferView = add_view(encode_attributes(positions.data(), positions.size() / 3, 12), 12,
                                 positions.size() / 3, "ATTRIBUTES", fallback_offset);
  position.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  position.type = TINYGLTF_TYPE_VEC3;
  position.count = positions.size() / 3;
  Bytes index_bytes(meshopt_encodeIndexBufferBound(indices.size(), positions.size() / 3));
  index_bytes.resize(
      meshopt_encodeIndexBuffer(index_bytes.data(), index_bytes.size(), indices.data(), indices.size()));
  tinygltf::Accessor index;
  index.bufferView = add_view(index_bytes, 2, indices.size(), "TRIANGLES", fallback_offset);
  index.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  index.type = TINYGLTF_TYPE_SCALAR;
  index.count = indices.size();
  model.accessors = {position, index};
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = 0;
  primitive.indices = 1;
  model.meshes.push_back({});
  model.meshes[0].primitives.push_back(primitive);
  model.nodes.push_back({});
  model.nodes[0].mesh = 0;
  model.scenes.push_back({});
  model.scenes[0].nodes = {0};
  return asset;
}

const std::vector<float> kPositions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
const std::vector<std::uint32_t> kIndices = {0, 1, 2, 2, 1, 3};

// The compressed bytes of every compressed view, in view order (bounds checked: a wrong offset fails).
std::vector<Bytes> compressed_sources(const Asset& asset) {
  std::vector<Bytes> out;
  std::string problem;
  for (const auto& view : asset.model.bufferViews)
    if (const auto source = meshopt_view(view, problem)) {
      const Bytes& data = asset.model.buffers.at(static_cast<std::size_t>(source->buffer)).data;
      EXPECT_LE(source->byte_offset + source->byte_length, data.size());
      if (source->byte_offset + source->byte_length > data.size()) return {};
      out.emplace_back(data.begin() + static_cast<long>(source->byte_offset),
                       data.begin() + static_cast<long>(source->byte_offset + source->byte_length));
    }
  return out;
}

TEST(MeshoptAsset, AccessorsReadThroughTheAssetDecodeOnceAndTheModelAloneRefuses) {
  const Asset asset = compressed_asset(kPositions, kIndices, 0);
  const long before = work_counters().views_decoded;
  AccessorProblem problem;
  const auto positions = read_accessor<float>(asset, 0, problem);
  ASSERT_TRUE(positions) << problem.text();
  EXPECT_EQ(positions->values, kPositions);
  EXPECT_EQ(read_accessor<float>(asset, 0, problem)->values, kPositions);
  EXPECT_EQ(work_counters().views_decoded - before, 1) << "the second read must reuse the decoded view";
  const auto indices = read_index_accessor(asset, 1, problem);
  ASSERT_TRUE(indices) << problem.text();
  ASSERT_EQ(indices->size(), kIndices.size());
  for (std::size_t t = 0; t < kIndices.size(); t += 3) {  // each triangle, up to a rotation of its corners
    const std::vector<std::uint32_t> got(indices->begin() + static_cast<long>(t), indices->begin() + static_cast<long>(t) + 3);
    std::vector<std::uint32_t> want(kIndices.begin() + static_cast<long>(t), kIndices.begin() + static_cast<long>(t) + 3);
    bool rotated = false;
    for (int r = 0; r < 3 && !rotated; ++r, std::rotate(want.begin(), want.begin() + 1, want.end())) rotated = got == want;
    EXPECT_TRUE(rotated) << "triangle " << t / 3;
  }
  EXPECT_FALSE(read_accessor<float>(asset.model, 0, problem));
  EXPECT_EQ(problem.pointer, "/bufferViews/0/extensions/EXT_meshopt_compression");
}

TEST(MeshoptAsset, CorruptCompressedBytesNameTheViewAndTheReason) {
  Asset asset = compressed_asset(kPositions, kIndices, 0);
  asset.model.buffers[0].data[0] = 0x00;  // the attribute stream's header
  AccessorProblem problem;
  EXPECT_FALSE(read_accessor<float>(asset, 0, problem));
  EXPECT_EQ(problem.pointer, "/bufferViews/0/extensions/EXT_meshopt_compression");
  EXPECT_NE(problem.reason.find("codec header"), std::string::npos) << problem.reason;
}

TEST(MeshoptAsset, SavedAsGltfAndGlbItStaysCompressedByteForByte) {
  test::ScratchDir scratch;
  for (const char* name : {"saved.gltf", "saved.glb"}) {
    Asset asset = compressed_asset(kPositions, kIndices, 0);
    asset.path = scratch / "input.gltf";
    const std::vector<Bytes> before = compressed_sources(asset);
    save_asset(asset, scratch / name);
    const Asset loaded = load_asset(scratch / name);
    EXPECT_EQ(compressed_sources(loaded), before) << name;
    ASSERT_EQ(loaded.model.buffers.size(), 2u) << name;
    EXPECT_TRUE(is_meshopt_placeholder(loaded.model.buffers[1])) << name;
    AccessorProblem problem;
    const auto positions = read_accessor<float>(loaded, 0, problem);
    ASSERT_TRUE(positions) << name << ": " << problem.text();
    EXPECT_EQ(positions->values, kPositions) << name;
  }
  // No file stands for the fallback buffer.
  for (const auto& file : test::files_under(scratch.path()))
    EXPECT_NE(file.filename(), "saved_1.bin") << "a fallback buffer was written out";
}

TEST(MeshoptAsset, PruningAnImageBesideCompressedBytesMovesThemAlong) {
  Asset asset = compressed_asset(kPositions, kIndices, 1000);
  const std::vector<Bytes> before = compressed_sources(asset);
  const PruneResult pruned = prune_unused(asset);  // the image has no texture: it goes
  EXPECT_EQ(pruned.images, 1);
  EXPECT_EQ(pruned.buffer_views, 1);
  EXPECT_LT(asset.model.buffers[0].data.size(), 1000u);
  EXPECT_EQ(compressed_sources(asset), before);
  AccessorProblem problem;
  const auto positions = read_accessor<float>(asset, 0, problem);
  ASSERT_TRUE(positions) << problem.text();
  EXPECT_EQ(positions->values, kPositions);
}

// Edits a bufferView's EXT_meshopt_compression object in place (tinygltf values are copied out and back).
template <class Edit>
void edit_meshopt_object(tinygltf::BufferView& view, Edit edit) {
  auto object = view.extensions["EXT_meshopt_compression"].Get<tinygltf::Value::Object>();
  edit(object);
  view.extensions["EXT_meshopt_compression"] = tinygltf::Value(object);
}

TEST(MeshoptAsset, PruningABufferBeforeTheSourcesRenumbersEveryViewThatNamesThem) {
  // buffers: 0 the image alone, 1 the sources, 2 the placeholder; the image goes, and with it buffer 0.
  Asset asset = compressed_asset(kPositions, kIndices, 64);
  tinygltf::Model& model = asset.model;
  const Bytes& all = model.buffers[0].data;
  tinygltf::Buffer image, sources;
  image.data.assign(all.begin(), all.begin() + 64);
  sources.data.assign(all.begin() + 64, all.end());
  model.buffers = {image, sources, model.buffers[1]};
  for (std::size_t v = 1; v < model.bufferViews.size(); ++v) {
    auto& view = model.bufferViews[v];
    view.buffer = 2;
    std::string problem;
    const auto source = meshopt_view(view, problem);
    ASSERT_TRUE(source) << problem;
    set_meshopt_source(view, 1, source->byte_offset - 64);
  }
  // The first view names its buffer as 1.0, which the schema counts as an integer.
  edit_meshopt_object(model.bufferViews[1], [](auto& object) { object["buffer"] = tinygltf::Value(1.0); });
  // A copy of a view whose extension is malformed (an unknown mode): it still names buffer 1.
  tinygltf::BufferView malformed = model.bufferViews[1];
  edit_meshopt_object(malformed, [](auto& object) { object["mode"] = tinygltf::Value(std::string("NOT_A_MODE")); });
  model.bufferViews.push_back(malformed);
  const std::vector<Bytes> before = compressed_sources(asset);

  const PruneResult pruned = prune_unused(asset);
  EXPECT_EQ(pruned.buffers, 1);
  ASSERT_EQ(model.buffers.size(), 2u);
  for (const auto& view : model.bufferViews) {
    EXPECT_EQ(view.buffer, 1) << "the placeholder";
    EXPECT_EQ(view.extensions.at("EXT_meshopt_compression").Get("buffer").GetNumberAsInt(), 0) << "the sources";
  }
  EXPECT_EQ(compressed_sources(asset), before);
  AccessorProblem problem;
  const auto positions = read_accessor<float>(asset, 0, problem);
  ASSERT_TRUE(positions) << problem.text();
  EXPECT_EQ(positions->values, kPositions);
}

TEST(MeshoptAsset, ABufferAMalformedObjectNamesIsNotCompacted) {
  // The image and the compressed bytes share buffer 0; the image goes. A malformed object naming
  // buffer 0 has no range to keep, so the buffer stays as it was rather than lose its bytes.
  Asset asset = compressed_asset(kPositions, kIndices, 64);
  tinygltf::Model& model = asset.model;
  tinygltf::BufferView malformed = model.bufferViews[1];
  edit_meshopt_object(malformed, [](auto& object) { object.erase("mode"); });
  model.bufferViews.push_back(malformed);
  const Bytes before = model.buffers[0].data;
  const std::vector<Bytes> sources = compressed_sources(asset);
  const PruneResult pruned = prune_unused(asset);
  EXPECT_EQ(pruned.images, 1);
  EXPECT_EQ(pruned.buffers, 0);
  EXPECT_EQ(model.buffers[0].data, before);
  EXPECT_EQ(compressed_sources(asset), sources);
  AccessorProblem problem;
  const auto positions = read_accessor<float>(asset, 0, problem);
  ASSERT_TRUE(positions) << problem.text();
  EXPECT_EQ(positions->values, kPositions);
}

// Buffers in the order a GLB save must renumber: the placeholder first, an image's buffer, then
// the buffer with the compressed bytes. Saved as .glb, the placeholder moves behind the BIN chunk.
TEST(MeshoptAsset, SavingAsGlbMergesTheSourcesAndMovesThePlaceholderBehindTheBinChunk) {
  test::ScratchDir scratch;
  Asset asset = compressed_asset(kPositions, kIndices, 64);
  asset.path = scratch / "input.gltf";
  tinygltf::Model& model = asset.model;
  // buffers: 0 image + sources, 1 placeholder  ->  0 placeholder, 1 image (64 bytes), 2 sources
  Bytes image(model.buffers[0].data.begin(), model.buffers[0].data.begin() + 64);
  Bytes sources(model.buffers[0].data.begin() + 64, model.buffers[0].data.end());
  model.buffers = {model.buffers[1], tinygltf::Buffer{}, tinygltf::Buffer{}};
  model.buffers[1].data = image;
  model.buffers[2].data = sources;
  model.bufferViews[0].buffer = 1;
  for (std::size_t v = 1; v < model.bufferViews.size(); ++v) {
    auto& view = model.bufferViews[v];
    view.buffer = 0;
    std::string problem;
    const auto source = meshopt_view(view, problem);
    ASSERT_TRUE(source) << problem;
    set_meshopt_source(view, 2, source->byte_offset - 64);
  }
  const std::vector<Bytes> before = compressed_sources(asset);
  AccessorProblem problem;
  ASSERT_TRUE(read_accessor<float>(asset, 0, problem)) << problem.text();
  save_asset(asset, scratch / "saved.glb");
  const Asset loaded = load_asset(scratch / "saved.glb");
  EXPECT_EQ(compressed_sources(loaded), before);
  ASSERT_EQ(loaded.model.buffers.size(), 2u);
  EXPECT_FALSE(is_meshopt_fallback(loaded.model.buffers[0])) << "the BIN chunk is no fallback";
  EXPECT_TRUE(is_meshopt_placeholder(loaded.model.buffers[1]));
  const auto positions = read_accessor<float>(loaded, 0, problem);
  ASSERT_TRUE(positions) << problem.text();
  EXPECT_EQ(positions->values, kPositions);
  // The placeholder's byteLength covers its views: positions (48 bytes) and indices at 48 (12).
  const std::string json = loaded.original_json;
  EXPECT_NE(json.find(R"("byteLength":60,"extensions":{"EXT_meshopt_compression":{"fallback":true}})"), std::string::npos)
      << json;
}

TEST(MeshoptAsset, ExtensionIntegersTheDocumentLibraryCannotHoldAreRefusedWithTheirPointer) {
  test::ScratchDir scratch;
  for (const char* value : {"1e20", "4294967304", "-1", "2.5"}) {
    Asset asset = compressed_asset(kPositions, kIndices, 0);
    asset.path = scratch / "input.gltf";
    save_asset(asset, scratch / "plain.gltf");
    std::string text = test::read_text(scratch / "plain.gltf");
    const std::size_t count = text.find(R"("count": 4)", text.find(R"("bufferViews")"));  // the extension's
    ASSERT_NE(count, std::string::npos) << text;
    text.replace(count, 10, std::string(R"("count": )") + value);
    test::write_text(scratch / "hostile.gltf", text);
    try {
      load_asset(scratch / "hostile.gltf");
      ADD_FAILURE() << value << " was loaded";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("/bufferViews/0/extensions/EXT_meshopt_compression/count"),
                std::string::npos)
          << error.what();
    }
  }
}

TEST(MeshoptAsset, ViewsSharingOneSourceDecodeNoMoreThanTheBudget) {
  // One 1 MiB attribute stream of zeros compresses to a few KiB; 64 views decode it each.
  const std::size_t count = 4096, stride = 256;
  const Bytes zeros(count * stride, 0);
  const Bytes compressed = encode_attributes(zeros.data(), count, stride);
  Asset asset;
  tinygltf::Model& model = asset.model;
  model.buffers.resize(2);
  model.buffers[0].data = compressed;
  model.buffers[1].extensions["EXT_meshopt_compression"] =
      tinygltf::Value(tinygltf::Value::Object{{"fallback", tinygltf::Value(true)}});
  for (int v = 0; v < 64; ++v) {
    tinygltf::BufferView view;
    view.buffer = 1;
    view.byteLength = count * stride;
    view.byteStride = stride;
    view.extensions["EXT_meshopt_compression"] = tinygltf::Value(tinygltf::Value::Object{
        {"buffer", tinygltf::Value(0)}, {"byteLength", tinygltf::Value(static_cast<int>(compressed.size()))},
        {"byteStride", tinygltf::Value(static_cast<int>(stride))}, {"count", tinygltf::Value(static_cast<int>(count))},
        {"mode", tinygltf::Value(std::string("ATTRIBUTES"))}});
    model.bufferViews.push_back(view);
  }
  const std::uint64_t budget = meshopt_decode_budget(compressed.size());
  std::uint64_t decoded = 0;
  int refused = 0;
  for (int v = 0; v < 64; ++v) {
    std::string problem;
    if (const auto bytes = buffer_view_bytes(asset, v, problem))
      decoded += bytes->size();
    else if (problem.find("64 times") != std::string::npos)
      ++refused;
    else
      ADD_FAILURE() << problem;
  }
  EXPECT_LE(decoded, budget);
  EXPECT_GT(refused, 0) << "64 MiB decoded from " << compressed.size() << " bytes";
  EXPECT_GT(decoded, 0u);
}

}  // namespace
}  // namespace gltf_pbr
