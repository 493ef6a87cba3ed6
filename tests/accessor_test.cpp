// core/accessor: what append_accessor writes, read_accessor reads back; byteStride, normalized
// integers (glTF 2.0 section 3.11) and sparse substitution (section 3.6.2.3) as the spec defines
// them; and every range that does not fit is refused with a JSON pointer, before allocating.
#include "core/accessor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <random>

#include "core/asset.hpp"
#include "core/error.hpp"

namespace gltf_pbr {
namespace {

template <typename T>
std::vector<std::uint8_t> bytes_of(const std::vector<T>& values) {
  std::vector<std::uint8_t> bytes(values.size() * sizeof(T));
  std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

template <typename Number>
AccessorValues<Number> read_ok(const tinygltf::Model& model, int index) {
  AccessorProblem problem;
  auto values = read_accessor<Number>(model, index, problem);
  EXPECT_TRUE(values) << problem.text();
  return values ? std::move(*values) : AccessorValues<Number>{};
}

AccessorProblem read_problem(const tinygltf::Model& model, int index) {
  AccessorProblem problem;
  EXPECT_FALSE(read_accessor<float>(model, index, problem)) << "accessor " << index << " should not read";
  EXPECT_FALSE(problem.reason.empty());
  return problem;
}

// Random component values of type T, across its whole range.
template <typename T>
std::vector<T> random_values(std::size_t count, std::mt19937& random) {
  std::vector<T> values(count);
  if constexpr (std::is_floating_point_v<T>) {
    std::uniform_real_distribution<T> distribution(-1e6, 1e6);
    for (T& v : values) v = distribution(random);
  } else {
    std::uniform_int_distribution<long long> distribution(std::numeric_limits<T>::min(), std::numeric_limits<T>::max());
    for (T& v : values) v = static_cast<T>(distribution(random));
  }
  return values;
}

template <typename T>
void expect_round_trip(int component_type, std::mt19937& random) {
  for (int type : {TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC2, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}) {
    const int components = tinygltf::GetNumComponentsInType(type);
    const std::vector<T> written = random_values<T>(static_cast<std::size_t>(components) * 37, random);
    tinygltf::Model model;
    const int index = append_accessor(model, written, component_type, type);
    ASSERT_EQ(model.accessors[static_cast<std::size_t>(index)].count, 37u);
    const auto as_double = read_ok<double>(model, index);
    const auto as_float = read_ok<float>(model, index);
    ASSERT_EQ(as_double.components, components);
    ASSERT_EQ(as_double.count(), 37u);
    ASSERT_EQ(as_float.values.size(), written.size());
    for (std::size_t i = 0; i < written.size(); ++i) {
      EXPECT_EQ(as_double.values[i], static_cast<double>(written[i])) << "component type " << component_type;
      EXPECT_EQ(as_float.values[i], static_cast<float>(written[i])) << "component type " << component_type;
    }
  }
}

TEST(Accessor, EveryComponentTypeRoundTripsExactly) {
  std::mt19937 random(7);
  expect_round_trip<std::int8_t>(TINYGLTF_COMPONENT_TYPE_BYTE, random);
  expect_round_trip<std::uint8_t>(TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, random);
  expect_round_trip<std::int16_t>(TINYGLTF_COMPONENT_TYPE_SHORT, random);
  expect_round_trip<std::uint16_t>(TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, random);
  expect_round_trip<std::uint32_t>(TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, random);
  expect_round_trip<float>(TINYGLTF_COMPONENT_TYPE_FLOAT, random);
}

// Every code of every normalizable type against the section 3.11 equations, and the properties
// they promise: the full range maps onto [0, 1] or [-1, 1], the two most negative signed codes
// both give -1, and the mapping never decreases.
template <typename T>
void expect_normalized(int component_type) {
  std::vector<T> codes;
  for (long long c = std::numeric_limits<T>::min(); c <= std::numeric_limits<T>::max(); ++c)
    codes.push_back(static_cast<T>(c));
  tinygltf::Model model;
  const int index = append_accessor(model, codes, component_type, TINYGLTF_TYPE_SCALAR);
  model.accessors[static_cast<std::size_t>(index)].normalized = true;
  const auto as_double = read_ok<double>(model, index);
  const auto as_float = read_ok<float>(model, index);
  ASSERT_EQ(as_double.values.size(), codes.size());
  const double max = std::numeric_limits<T>::max();
  for (std::size_t i = 0; i < codes.size(); ++i) {
    const double expected = std::max(codes[i] / max, -1.0);
    EXPECT_EQ(as_double.values[i], expected) << +codes[i];
    EXPECT_EQ(as_float.values[i], std::max(static_cast<float>(codes[i]) / static_cast<float>(max), -1.0f)) << +codes[i];
    EXPECT_NEAR(as_float.values[i], expected, 1e-7) << +codes[i];
    if (i > 0) {
      EXPECT_LE(as_double.values[i - 1], as_double.values[i]) << +codes[i];
    }
  }
  EXPECT_EQ(as_double.values.back(), 1.0);
  EXPECT_EQ(as_double.values.front(), std::is_signed_v<T> ? -1.0 : 0.0);
  if (std::is_signed_v<T>) {
    EXPECT_EQ(as_double.values[1], -1.0);
  }
}

TEST(Accessor, NormalizedIntegersFollowSection3_11ForEveryCode) {
  expect_normalized<std::int8_t>(TINYGLTF_COMPONENT_TYPE_BYTE);
  expect_normalized<std::uint8_t>(TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE);
  expect_normalized<std::int16_t>(TINYGLTF_COMPONENT_TYPE_SHORT);
  expect_normalized<std::uint16_t>(TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
}

// Interleaved vertices, 20 bytes apart: VEC3 float position, VEC2 normalized uint16 UV, 4 bytes of
// padding. Two accessors share the view through byteOffset and byteStride.
TEST(Accessor, Mat4ReadsSixteenComponentsColumnByColumn) {
  // Two inverse bind matrices (section 3.7.3.2), column-major as stored.
  std::vector<float> matrices(32);
  for (std::size_t i = 0; i < matrices.size(); ++i) matrices[i] = static_cast<float>(i) - 7.5f;
  tinygltf::Model model;
  const int index = append_accessor(model, matrices, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4);
  const auto values = read_ok<double>(model, index);
  EXPECT_EQ(values.components, 16);
  ASSERT_EQ(values.count(), 2u);
  for (std::size_t i = 0; i < matrices.size(); ++i) EXPECT_EQ(values.values[i], matrices[i]);
}

TEST(Accessor, InterleavedAttributesReadThroughByteStride) {
  struct Vertex {
    float position[3];
    std::uint16_t uv[2];
    std::uint32_t padding;
  };
  static_assert(sizeof(Vertex) == 20);
  std::vector<Vertex> vertices;
  for (std::uint16_t i = 0; i < 5; ++i)
    vertices.push_back({{1.0f * i, 2.0f * i, -3.0f * i}, {static_cast<std::uint16_t>(i * 1000), 65535}, 0xDEADBEEF});
  tinygltf::Model model;
  const int view = append_buffer_view(model, bytes_of(vertices));
  model.bufferViews[static_cast<std::size_t>(view)].byteStride = sizeof(Vertex);
  tinygltf::Accessor positions;
  positions.bufferView = view;
  positions.byteOffset = 0;
  positions.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  positions.type = TINYGLTF_TYPE_VEC3;
  positions.count = vertices.size();
  tinygltf::Accessor uvs = positions;
  uvs.byteOffset = offsetof(Vertex, uv);
  uvs.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  uvs.type = TINYGLTF_TYPE_VEC2;
  uvs.normalized = true;
  model.accessors = {positions, uvs};

  const auto read_positions = read_ok<float>(model, 0);
  const auto read_uvs = read_ok<double>(model, 1);
  ASSERT_EQ(read_positions.count(), vertices.size());
  ASSERT_EQ(read_uvs.count(), vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(read_positions.values[i * 3 + c], vertices[i].position[c]);
    EXPECT_EQ(read_uvs.values[i * 2], vertices[i].uv[0] / 65535.0);
    EXPECT_EQ(read_uvs.values[i * 2 + 1], 1.0);
  }

  // The last element needs only its own bytes, not a whole stride: 20 x 4 + 16 bytes fit exactly.
  model.bufferViews[static_cast<std::size_t>(view)].byteLength = sizeof(Vertex) * 4 + 16;
  EXPECT_EQ(read_ok<float>(model, 1).count(), vertices.size());
  model.bufferViews[static_cast<std::size_t>(view)].byteLength -= 1;
  EXPECT_EQ(read_problem(model, 1).pointer, "/accessors/1");
}

// Sparse substitution over a dense base and over no bufferView at all (zeros), with each index
// component type; sparse data is tightly packed whatever the view's byteStride says.
TEST(Accessor, SparseValuesReplaceTheNamedElements) {
  for (int index_type : {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                         TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT})
    for (bool dense_base : {true, false}) {
      tinygltf::Model model;
      const std::vector<float> base = {1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6};
      const int accessor_index = append_accessor(model, base, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2);
      tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(accessor_index)];
      if (!dense_base) accessor.bufferView = -1;  // zeros until the sparse values land
      const std::vector<std::uint32_t> targets = {0, 3, 5};
      std::vector<std::uint8_t> index_bytes;
      for (std::uint32_t t : targets) {
        std::uint8_t packed[4];
        std::memcpy(packed, &t, 4);  // little-endian: the low bytes come first
        const int size = index_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                         : index_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                                                                                : 4;
        index_bytes.insert(index_bytes.end(), packed, packed + size);
      }
      const std::vector<float> replacements = {-10, -11, -40, -41, -60, -61};
      accessor.sparse.isSparse = true;
      accessor.sparse.count = static_cast<int>(targets.size());
      accessor.sparse.indices.bufferView = append_buffer_view(model, index_bytes);
      accessor.sparse.indices.byteOffset = 0;  // tinygltf leaves these uninitialized
      accessor.sparse.indices.componentType = index_type;
      accessor.sparse.values.bufferView = append_buffer_view(model, bytes_of(replacements));
      accessor.sparse.values.byteOffset = 0;
      model.bufferViews.back().byteStride = 64;  // ignored for sparse values

      std::vector<double> expected =
          dense_base ? std::vector<double>(base.begin(), base.end()) : std::vector<double>(12);
      for (std::size_t s = 0; s < targets.size(); ++s)
        for (std::size_t c = 0; c < 2; ++c) expected[targets[s] * 2 + c] = replacements[s * 2 + c];
      EXPECT_EQ(read_ok<double>(model, accessor_index).values, expected)
          << "index type " << index_type << (dense_base ? ", dense base" : ", no bufferView");
    }
}

// A file with one good accessor (0) and broken copies of it: each refusal names where it is.
TEST(Accessor, RangesThatDoNotFitAreRefusedWithAPointer) {
  tinygltf::Model model;
  const int good =
      append_accessor(model, std::vector<float>(12, 0.5f), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  ASSERT_EQ(read_ok<float>(model, good).count(), 4u);
  auto broken = [&](auto&& edit) {
    tinygltf::Model copy = model;
    edit(copy.accessors[0], copy);
    return read_problem(copy, 0);
  };
  // Counts far beyond the buffer, including ones whose byte size overflows size_t, fail before any
  // allocation (a real allocation of 2^62 VEC3 would throw bad_alloc instead).
  for (std::size_t count :
       {std::size_t{5}, std::size_t{1'000'000'000'000}, std::size_t{1} << 62, std::numeric_limits<std::size_t>::max()})
    EXPECT_EQ(broken([&](tinygltf::Accessor& a, tinygltf::Model&) { a.count = count; }).pointer, "/accessors/0")
        << count;
  EXPECT_EQ(broken([](tinygltf::Accessor& a, tinygltf::Model&) { a.byteOffset = std::size_t{1} << 63; }).pointer,
            "/accessors/0");
  EXPECT_EQ(broken([](tinygltf::Accessor& a, tinygltf::Model&) { a.bufferView = 9; }).pointer,
            "/accessors/0/bufferView");
  EXPECT_EQ(broken([](tinygltf::Accessor&, tinygltf::Model& m) { m.bufferViews[0].buffer = 3; }).pointer,
            "/bufferViews/0/buffer");
  EXPECT_EQ(broken([](tinygltf::Accessor&, tinygltf::Model& m) { m.bufferViews[0].byteLength += 1; }).pointer,
            "/bufferViews/0");
  EXPECT_EQ(broken([](tinygltf::Accessor&, tinygltf::Model& m) {
              m.bufferViews[0].byteOffset = std::numeric_limits<std::size_t>::max() - 2;
            }).pointer,
            "/bufferViews/0");
  EXPECT_EQ(broken([](tinygltf::Accessor& a, tinygltf::Model&) { a.type = TINYGLTF_TYPE_MAT3; }).pointer,
            "/accessors/0/type");
  EXPECT_EQ(broken([](tinygltf::Accessor& a, tinygltf::Model&) { a.componentType = 5130; }).pointer,  // double
            "/accessors/0/componentType");
  EXPECT_EQ(broken([](tinygltf::Accessor& a, tinygltf::Model&) {
              a.bufferView = -1;
              a.count = (std::size_t{1} << 28) + 1;
            }).pointer,
            "/accessors/0/count");
  EXPECT_EQ(read_problem(model, 1).pointer, "/accessors/1");
  EXPECT_EQ(read_problem(model, -1).pointer, "/accessors/-1");

  // Sparse: indices past the accessor's count, a negative count, a float index type, and index
  // data past its view.
  const int sparse_indices = append_buffer_view(model, bytes_of(std::vector<std::uint8_t>{1, 4}));
  model.accessors[0].sparse.isSparse = true;
  model.accessors[0].sparse.count = 2;
  model.accessors[0].sparse.indices.bufferView = sparse_indices;
  model.accessors[0].sparse.indices.byteOffset = 0;
  model.accessors[0].sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  model.accessors[0].sparse.values.bufferView = 0;
  model.accessors[0].sparse.values.byteOffset = 0;
  EXPECT_EQ(read_problem(model, 0).pointer, "/accessors/0/sparse/indices");
  EXPECT_EQ(broken([](tinygltf::Accessor& a, tinygltf::Model&) { a.sparse.count = -1; }).pointer,
            "/accessors/0/sparse/count");
  EXPECT_EQ(broken([](tinygltf::Accessor& a, tinygltf::Model&) {
              a.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
            }).pointer,
            "/accessors/0/sparse/indices/componentType");
  EXPECT_EQ(broken([](tinygltf::Accessor& a, tinygltf::Model&) { a.sparse.count = 3; }).pointer,
            "/accessors/0/sparse/indices");
  EXPECT_EQ(broken([](tinygltf::Accessor& a, tinygltf::Model&) { a.sparse.values.bufferView = 7; }).pointer,
            "/accessors/0/sparse/values/bufferView");
}

TEST(Accessor, IndicesReadExactlyAndOnlyFromUnsignedScalars) {
  tinygltf::Model model;
  const std::vector<std::uint32_t> big = {0, 16'777'217, 0xFFFFFFFFu};  // 2^24 + 1 is not a float
  const int index32 = append_accessor(model, big, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR);
  const int index8 = append_accessor(model, std::vector<std::uint8_t>{255, 0, 7}, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                     TINYGLTF_TYPE_SCALAR);
  const int floats =
      append_accessor(model, std::vector<float>{0, 1, 2}, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR);
  AccessorProblem problem;
  EXPECT_EQ(read_index_accessor(model, index32, problem), big) << problem.text();
  EXPECT_EQ(read_index_accessor(model, index8, problem), (std::vector<std::uint32_t>{255, 0, 7})) << problem.text();
  EXPECT_FALSE(read_index_accessor(model, floats, problem));
  EXPECT_EQ(problem.pointer, "/accessors/2");

  // The throwing form names the file, the pointer and the reason.
  Asset asset;
  asset.path = "indices.gltf";
  asset.model = model;
  try {
    read_index_accessor_or_throw(asset, floats);
    ADD_FAILURE() << "float indices were read";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file, "indices.gltf");
    EXPECT_EQ(error.pointer, "/accessors/2");
  }
  EXPECT_THROW(read_accessor_or_throw(asset, 3), InputError);
  EXPECT_EQ(read_accessor_or_throw(asset, index8).values, (std::vector<double>{255, 0, 7}));
}

}  // namespace
}  // namespace gltf_pbr
