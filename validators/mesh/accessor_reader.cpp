#include "validators/mesh/accessor_reader.hpp"

#include <algorithm>
#include <cstring>

namespace gltf_pbr::mesh {

namespace {

int component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;  // matrices never appear in mesh attributes the checks read
  }
}

template <typename T>
T load_unaligned(const std::uint8_t* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

// One component as float. Normalized integers use the glTF 2.0 section 3.11 formulas, e.g.
// f = max(c / 127.0, -1.0) for signed bytes.
float component_as_float(const std::uint8_t* bytes, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return load_unaligned<float>(bytes);
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const float c = load_unaligned<std::int8_t>(bytes);
      return normalized ? std::max(c / 127.0f, -1.0f) : c;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const float c = load_unaligned<std::uint8_t>(bytes);
      return normalized ? c / 255.0f : c;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const float c = load_unaligned<std::int16_t>(bytes);
      return normalized ? std::max(c / 32767.0f, -1.0f) : c;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const float c = load_unaligned<std::uint16_t>(bytes);
      return normalized ? c / 65535.0f : c;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return static_cast<float>(load_unaligned<std::uint32_t>(bytes));
    default:
      return 0.0f;
  }
}

std::uint32_t component_as_index(const std::uint8_t* bytes, int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return load_unaligned<std::uint8_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return load_unaligned<std::uint16_t>(bytes);
    default:
      return load_unaligned<std::uint32_t>(bytes);
  }
}

// Where `count` elements of `element_size` bytes start inside a bufferView, with its stride:
// null with `problem` set when they do not fit.
const std::uint8_t* view_elements(const tinygltf::Model& model, int view_index, std::size_t byte_offset,
                                  std::size_t count, std::size_t element_size, std::size_t& stride,
                                  std::string& problem) {
  if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size()) {
    problem = "bufferView index is out of range";
    return nullptr;
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
    problem = "buffer index is out of range";
    return nullptr;
  }
  const tinygltf::Buffer& buffer = model.buffers[static_cast<std::size_t>(view.buffer)];
  stride = view.byteStride ? view.byteStride : element_size;
  const std::size_t needed = count == 0 ? 0 : byte_offset + (count - 1) * stride + element_size;
  if (view.byteOffset + view.byteLength > buffer.data.size() || needed > view.byteLength) {
    problem = "accessor data lies outside its bufferView or buffer";
    return nullptr;
  }
  return buffer.data.data() + view.byteOffset + byte_offset;
}

}  // namespace

std::optional<FloatArray> read_float_accessor(const tinygltf::Model& model, int accessor_index, std::string& problem) {
  if (accessor_index < 0 || static_cast<std::size_t>(accessor_index) >= model.accessors.size()) {
    problem = "accessor index is out of range";
    return std::nullopt;
  }
  const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(accessor_index)];
  const int components = component_count(accessor.type);
  const int size = component_size(accessor.componentType);
  if (components == 0 || size == 0) {
    problem = "accessor type or componentType is not a vector of numbers";
    return std::nullopt;
  }
  FloatArray out;
  out.components = components;
  const std::size_t element_size = static_cast<std::size_t>(components * size);
  const std::uint8_t* data = nullptr;
  std::size_t stride = 0;
  if (accessor.bufferView >= 0) {
    // Bounds first, so a bogus count fails here instead of in a huge allocation.
    data =
        view_elements(model, accessor.bufferView, accessor.byteOffset, accessor.count, element_size, stride, problem);
    if (!data) return std::nullopt;
  } else if (accessor.count > (std::size_t{1} << 28)) {
    // Without a bufferView an accessor is zeros plus its sparse values (glTF 2.0 section 3.6.2.3)
    // and no buffer bounds its count: 2^28 elements caps what a hostile file makes us allocate.
    problem = "accessor without bufferView has more than 2^28 elements";
    return std::nullopt;
  }
  out.values.assign(accessor.count * static_cast<std::size_t>(components), 0.0f);
  if (data) {
    for (std::size_t i = 0; i < accessor.count; ++i)
      for (int c = 0; c < components; ++c)
        out.values[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)] = component_as_float(
            data + i * stride + static_cast<std::size_t>(c * size), accessor.componentType, accessor.normalized);
  }
  if (accessor.sparse.isSparse) {
    // Sparse substitution (glTF 2.0 section 3.6.2.3): tightly packed indices and values.
    const auto& sparse = accessor.sparse;
    if (sparse.count < 0 || sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) {
      problem = "sparse count or byteOffset is negative";
      return std::nullopt;
    }
    const std::size_t sparse_count = static_cast<std::size_t>(sparse.count);
    const int index_size = component_size(sparse.indices.componentType);
    std::size_t index_stride = 0, value_stride = 0;
    const std::uint8_t* indices =
        view_elements(model, sparse.indices.bufferView, static_cast<std::size_t>(sparse.indices.byteOffset),
                      sparse_count, static_cast<std::size_t>(index_size), index_stride, problem);
    const std::uint8_t* values =
        indices ? view_elements(model, sparse.values.bufferView, static_cast<std::size_t>(sparse.values.byteOffset),
                                sparse_count, element_size, value_stride, problem)
                : nullptr;
    if (!values || index_size == 0) {
      if (problem.empty()) problem = "sparse indices have a bad componentType";
      return std::nullopt;
    }
    for (std::size_t s = 0; s < sparse_count; ++s) {
      // Sparse data is tightly packed, whatever the bufferView's stride says.
      const std::uint32_t target =
          component_as_index(indices + s * static_cast<std::size_t>(index_size), sparse.indices.componentType);
      if (target >= accessor.count) {
        problem = "sparse index is out of range";
        return std::nullopt;
      }
      for (int c = 0; c < components; ++c)
        out.values[target * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)] =
            component_as_float(values + s * element_size + static_cast<std::size_t>(c * size), accessor.componentType,
                               accessor.normalized);
    }
  }
  return out;
}

std::optional<std::vector<std::uint32_t>> read_index_accessor(const tinygltf::Model& model, int accessor_index,
                                                              std::string& problem) {
  if (accessor_index < 0 || static_cast<std::size_t>(accessor_index) >= model.accessors.size()) {
    problem = "accessor index is out of range";
    return std::nullopt;
  }
  const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(accessor_index)];
  const int type = accessor.componentType;
  if (accessor.type != TINYGLTF_TYPE_SCALAR ||
      (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
       type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
    problem = "indices accessor is not SCALAR UNSIGNED_BYTE/SHORT/INT";
    return std::nullopt;
  }
  if (accessor.sparse.isSparse || accessor.bufferView < 0) {
    // Rare for indices; the float path handles sparse and view-less data exactly up to 2^24,
    // which covers every index a float-addressable vertex array can use.
    auto as_floats = read_float_accessor(model, accessor_index, problem);
    if (!as_floats) return std::nullopt;
    std::vector<std::uint32_t> indices(as_floats->values.size());
    for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<std::uint32_t>(as_floats->values[i]);
    return indices;
  }
  const std::size_t size = static_cast<std::size_t>(component_size(type));
  std::size_t stride = 0;
  const std::uint8_t* data =
      view_elements(model, accessor.bufferView, accessor.byteOffset, accessor.count, size, stride, problem);
  if (!data) return std::nullopt;
  std::vector<std::uint32_t> indices(accessor.count);
  for (std::size_t i = 0; i < accessor.count; ++i) indices[i] = component_as_index(data + i * stride, type);
  return indices;
}

}  // namespace gltf_pbr::mesh
