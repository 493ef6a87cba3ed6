// Reading glTF accessors into plain arrays (glTF 2.0 section 3.6.2: byteStride, sparse
// substitution, accessors without a bufferView; section 3.11: normalized integers), and the writing
// counterpart that generated assets (tests, benches) use to lay data out the same way.
// Every range is checked against its bufferView and buffer before anything is allocated, so a
// hostile `count` fails with a reason instead of in a huge allocation.
#pragma once
#include <tiny_gltf.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace gltf_pbr {

struct Asset;

// Why an accessor could not be read: where (a JSON pointer, RFC 6901) and why.
struct AccessorProblem {
  std::string pointer;  // e.g. "/accessors/3/sparse/indices/bufferView"
  std::string reason;
  std::string text() const { return pointer + ": " + reason; }
};

// An accessor's elements, `components` numbers each, interleaved: element i's component c is
// values[i * components + c].
template <typename Number>
struct AccessorValues {
  std::vector<Number> values;
  int components = 0;  // 1 SCALAR, 2 VEC2, 3 VEC3, 4 VEC4, 16 MAT4 (column-major)
  std::size_t count() const { return components > 0 ? values.size() / static_cast<std::size_t>(components) : 0; }
};

// Accessor `index` of a SCALAR, VEC2-VEC4 or MAT4 type (vertex attributes, indices, inverse bind
// matrices; MAT2 and MAT3 are refused). Normalized integers map to [0, 1] or [-1, 1] by the
// section 3.11 equations, e.g. max(c / 127, -1) for signed bytes, computed in Number. Number is
// float or double (double holds every component value exactly). Returns nothing, with `problem`
// set, when the accessor does not fit its buffers or names something that does not exist.
template <typename Number>
std::optional<AccessorValues<Number>> read_accessor(const tinygltf::Model& model, int index, AccessorProblem& problem);
extern template std::optional<AccessorValues<float>> read_accessor(const tinygltf::Model&, int, AccessorProblem&);
extern template std::optional<AccessorValues<double>> read_accessor(const tinygltf::Model&, int, AccessorProblem&);

// The same through an Asset, which also reads bufferViews compressed with EXT_meshopt_compression
// (decoded once, on first read); the Model overloads refuse those.
template <typename Number>
std::optional<AccessorValues<Number>> read_accessor(const Asset& asset, int index, AccessorProblem& problem);
extern template std::optional<AccessorValues<float>> read_accessor(const Asset&, int, AccessorProblem&);
extern template std::optional<AccessorValues<double>> read_accessor(const Asset&, int, AccessorProblem&);

// An indices accessor: SCALAR UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT (glTF 2.0 section
// 3.7.2.1), exactly, sparse or not.
std::optional<std::vector<std::uint32_t>> read_index_accessor(const tinygltf::Model& model, int index,
                                                              AccessorProblem& problem);
std::optional<std::vector<std::uint32_t>> read_index_accessor(const Asset& asset, int index, AccessorProblem& problem);

// The same for callers that stop at bad input: throw InputError naming the asset's file, the
// JSON pointer and the reason.
AccessorValues<double> read_accessor_or_throw(const Asset& asset, int index);
std::vector<std::uint32_t> read_index_accessor_or_throw(const Asset& asset, int index);

// --- Writing ---

// Appends `bytes` to buffer 0 (created when missing) as a new bufferView starting on a 4-byte
// boundary (glTF 2.0 section 3.6.2.4 alignment); returns the view's index.
int append_buffer_view(tinygltf::Model& model, std::span<const std::uint8_t> bytes);

// Appends `elements` as a new bufferView and a tightly packed accessor over it of `type` x
// `component_type`; its count is the byte size over the element size. Returns the accessor index.
int append_accessor(tinygltf::Model& model, std::span<const std::uint8_t> elements, int component_type, int type);
template <typename T>
int append_accessor(tinygltf::Model& model, const std::vector<T>& elements, int component_type, int type) {
  return append_accessor(model, {reinterpret_cast<const std::uint8_t*>(elements.data()), elements.size() * sizeof(T)},
                         component_type, type);
}

}  // namespace gltf_pbr
