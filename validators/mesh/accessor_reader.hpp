// Reads glTF accessors into plain arrays for the mesh checks: byteStride, normalized integer
// types and sparse substitution handled (glTF 2.0 sections 3.6.2 and 3.11).
// Core has no accessor reader yet; this one could move to core/ when a second step needs it.
#pragma once
#include <tiny_gltf.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gltf_pbr::mesh {

struct FloatArray {
  std::vector<float> values;  // count * components, interleaved per element
  int components = 0;         // 1 SCALAR, 2 VEC2, 3 VEC3, 4 VEC4
  std::size_t count() const { return components ? values.size() / static_cast<std::size_t>(components) : 0; }
};

// The accessor's elements as floats; integer types are normalized to [0,1] or [-1,1] when the
// accessor says `normalized` (the dequantization equations of glTF 2.0 section 3.11).
// Returns nothing with `problem` set when the accessor does not fit its buffer: the structure
// step reports that with the Khronos code, so the mesh checks only skip the primitive.
std::optional<FloatArray> read_float_accessor(const tinygltf::Model& model, int accessor_index, std::string& problem);

// An indices accessor (UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT) as 32-bit indices.
std::optional<std::vector<std::uint32_t>> read_index_accessor(const tinygltf::Model& model, int accessor_index,
                                                              std::string& problem);

}  // namespace gltf_pbr::mesh
