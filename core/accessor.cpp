#include "core/accessor.hpp"

#include <algorithm>
#include <cstring>
#include <type_traits>

#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/meshopt.hpp"

namespace gltf_pbr {
namespace {

// An accessor without a bufferView is zeros plus its sparse values (glTF 2.0 section 3.6.2.3), and
// no buffer bounds its count: 2^28 elements caps what a hostile file makes us allocate.
constexpr std::size_t kMaxElementsWithoutBufferView = std::size_t{1} << 28;

// Bytes per component (glTF 2.0 section 3.6.2.2); 0 for anything else.
std::size_t component_size(int component_type) {
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

// Components per element of the vector types and MAT4; 0 for MAT2 and MAT3 (their byte and short
// columns are padded to 4 bytes, section 3.6.2.4, and no caller reads them) and anything else.
// A MAT4 column is 4, 8 or 16 bytes, never padded; its 16 components come column by column.
int vector_components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      return 0;
  }
}

bool is_unsigned_index_type(int component_type) {
  return component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

template <typename T>
T load_unaligned(const std::uint8_t* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

// One component as Number. Normalized integers use the glTF 2.0 section 3.11 equations in Number's
// precision (f = c / 255.0 for unsigned bytes, f = max(c / 127.0, -1.0) for signed bytes, ...).
template <typename Number>
Number decode_component(const std::uint8_t* bytes, int component_type, bool normalized) {
  auto integer = [&](auto zero, Number scale, bool is_signed) -> Number {
    const Number c = static_cast<Number>(load_unaligned<decltype(zero)>(bytes));
    if constexpr (std::is_floating_point_v<Number>) {
      if (normalized) return is_signed ? std::max(c / scale, Number(-1)) : c / scale;
    }
    return c;
  };
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return static_cast<Number>(load_unaligned<float>(bytes));
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return integer(std::int8_t{}, Number(127), true);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return integer(std::uint8_t{}, Number(255), false);
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return integer(std::int16_t{}, Number(32767), true);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return integer(std::uint16_t{}, Number(65535), false);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:  // never normalized (section 3.11 lists no such case)
      return static_cast<Number>(load_unaligned<std::uint32_t>(bytes));
    default:
      return Number(0);
  }
}

// `count` elements of `element_size` bytes, `stride` apart, found and bounds-checked inside a
// bufferView. Sparse data is tightly packed whatever the view says (section 3.6.2.3).
struct ElementRun {
  const std::uint8_t* first = nullptr;
  std::size_t stride = 0;
};

// Whether `count` elements of `element_size` bytes, `stride` apart from `offset`, fit in `length`
// bytes. Written without overflow: counts and offsets come straight from the file.
bool run_fits(std::size_t offset, std::size_t count, std::size_t stride, std::size_t element_size, std::size_t length) {
  if (count == 0) return true;
  if (offset > length || element_size > length - offset) return false;
  return count - 1 <= (length - offset - element_size) / stride;
}

// The bytes of bufferView `view_index`: a range of its buffer or, when EXT_meshopt_compression
// compresses it, its decoded bytes, which only an Asset keeps (core/meshopt.hpp). `reference`
// names the property that refers to the view (blamed when the view does not exist).
std::optional<std::span<const std::uint8_t>> view_bytes(const tinygltf::Model& model, const Asset* asset,
                                                        int view_index, const std::string& reference,
                                                        AccessorProblem& problem) {
  if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size()) {
    problem = {reference, "bufferView " + std::to_string(view_index) + " does not exist"};
    return std::nullopt;
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  const std::string where = pointer("bufferViews", view_index);
  auto buffer_range = [&](std::int64_t buffer_index, std::uint64_t offset, std::uint64_t length,
                          const std::string& at) -> std::optional<std::span<const std::uint8_t>> {
    if (buffer_index < 0 || static_cast<std::size_t>(buffer_index) >= model.buffers.size()) {
      problem = {at + "/buffer", "buffer " + std::to_string(buffer_index) + " does not exist"};
      return std::nullopt;
    }
    const std::vector<unsigned char>& buffer = model.buffers[static_cast<std::size_t>(buffer_index)].data;
    if (offset > buffer.size() || length > buffer.size() - offset) {
      problem = {at, "byteOffset " + std::to_string(offset) + " + byteLength " + std::to_string(length) +
                         " exceed its buffer's " + std::to_string(buffer.size()) + " bytes"};
      return std::nullopt;
    }
    return std::span<const std::uint8_t>(buffer.data() + offset, static_cast<std::size_t>(length));
  };
  std::string meshopt_problem;
  const std::optional<MeshoptView> compressed = meshopt_view(view, meshopt_problem);
  const std::string extension = where + "/extensions/EXT_meshopt_compression";
  if (!meshopt_problem.empty()) {
    problem = {extension, meshopt_problem};
    return std::nullopt;
  }
  if (!compressed) return buffer_range(view.buffer, view.byteOffset, view.byteLength, where);
  if (!asset) {
    problem = {extension, "a compressed bufferView is read through the Asset that decodes it"};
    return std::nullopt;
  }
  const std::string layout = meshopt_layout_problem(*compressed, view.byteLength, view.byteStride);
  if (!layout.empty()) {
    problem = {extension, layout};
    return std::nullopt;
  }
  const auto source = buffer_range(compressed->buffer, compressed->byte_offset, compressed->byte_length, extension);
  if (!source) return std::nullopt;
  std::uint64_t stored = 0;
  for (const auto& buffer : model.buffers) stored += buffer.data.size();
  const DecodedViews::Entry& decoded = asset->decoded_views.find_or_decode(
      view_index, view.byteLength, meshopt_decode_budget(stored),
      [&](std::string& why) { return decode_meshopt(*source, *compressed, why); });
  if (!decoded.bytes) {
    problem = {extension, decoded.problem};
    return std::nullopt;
  }
  return std::span<const std::uint8_t>(*decoded.bytes);
}

// `reference` names the bufferView property (blamed when the view or its buffer is missing),
// `run` the object whose byteOffset and count place the elements (blamed when they do not fit).
std::optional<ElementRun> find_elements(const tinygltf::Model& model, const Asset* asset, int view_index,
                                        const std::string& reference, const std::string& run, std::size_t byte_offset,
                                        std::size_t count, std::size_t element_size, bool use_view_stride,
                                        AccessorProblem& problem) {
  const auto bytes = view_bytes(model, asset, view_index, reference, problem);
  if (!bytes) return std::nullopt;
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  const std::size_t stride = use_view_stride && view.byteStride > 0 ? view.byteStride : element_size;
  if (!run_fits(byte_offset, count, stride, element_size, bytes->size())) {
    problem = {run, std::to_string(count) + " elements of " + std::to_string(element_size) + " bytes, " +
                        std::to_string(stride) + " apart from byteOffset " + std::to_string(byte_offset) +
                        ", do not fit in bufferView " + std::to_string(view_index) + " (" +
                        std::to_string(bytes->size()) + " bytes)"};
    return std::nullopt;
  }
  // Only a non-empty run points into the bytes (an offset past their end is never formed).
  return ElementRun{count == 0 ? bytes->data() : bytes->data() + byte_offset, stride};
}

// read_accessor for Number float or double, and std::uint32_t for indices (whose component types
// the caller has checked to be unsigned integers).
template <typename Number>
std::optional<AccessorValues<Number>> read_elements(const tinygltf::Model& model, const Asset* asset, int index,
                                                    AccessorProblem& problem) {
  const std::string where = pointer("accessors", index);
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
    problem = {where, "accessor does not exist"};
    return std::nullopt;
  }
  const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
  const int components = vector_components(accessor.type);
  if (components == 0) {
    problem = {where + "/type", "is not SCALAR, VEC2-VEC4 or MAT4"};
    return std::nullopt;
  }
  const std::size_t size = component_size(accessor.componentType);
  if (size == 0) {
    problem = {where + "/componentType", std::to_string(accessor.componentType) + " is not a glTF component type"};
    return std::nullopt;
  }
  const std::size_t per_element = static_cast<std::size_t>(components);
  const std::size_t element_size = per_element * size;
  auto decode_element = [&](const std::uint8_t* element, Number* out) {
    for (std::size_t c = 0; c < per_element; ++c)
      out[c] = decode_component<Number>(element + c * size, accessor.componentType, accessor.normalized);
  };

  // Bounds first, then the allocation they justify.
  std::optional<ElementRun> dense;
  if (accessor.bufferView >= 0) {
    dense = find_elements(model, asset, accessor.bufferView, where + "/bufferView", where, accessor.byteOffset, accessor.count,
                          element_size, true, problem);
    if (!dense) return std::nullopt;
  } else if (accessor.count > kMaxElementsWithoutBufferView) {
    problem = {where + "/count", "more than 2^28 elements without a bufferView"};
    return std::nullopt;
  }
  AccessorValues<Number> out;
  out.components = components;
  out.values.assign(accessor.count * per_element, Number(0));
  if (dense)
    for (std::size_t i = 0; i < accessor.count; ++i)
      decode_element(dense->first + i * dense->stride, &out.values[i * per_element]);

  if (!accessor.sparse.isSparse) return out;
  // Sparse substitution (section 3.6.2.3): `count` tightly packed indices, strictly increasing in
  // a valid file, each naming the element that the matching value replaces.
  const auto& sparse = accessor.sparse;
  const std::string sparse_where = where + "/sparse";
  if (sparse.count < 0) {
    problem = {sparse_where + "/count", "is negative"};
    return std::nullopt;
  }
  if (!is_unsigned_index_type(sparse.indices.componentType)) {
    problem = {sparse_where + "/indices/componentType", "is not UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT"};
    return std::nullopt;
  }
  if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) {
    problem = {sparse_where + (sparse.indices.byteOffset < 0 ? "/indices" : "/values") + "/byteOffset", "is negative"};
    return std::nullopt;
  }
  const std::size_t sparse_count = static_cast<std::size_t>(sparse.count);
  const std::size_t index_size = component_size(sparse.indices.componentType);
  const auto indices =
      find_elements(model, asset, sparse.indices.bufferView, sparse_where + "/indices/bufferView", sparse_where + "/indices",
                    static_cast<std::size_t>(sparse.indices.byteOffset), sparse_count, index_size, false, problem);
  if (!indices) return std::nullopt;
  const auto values =
      find_elements(model, asset, sparse.values.bufferView, sparse_where + "/values/bufferView", sparse_where + "/values",
                    static_cast<std::size_t>(sparse.values.byteOffset), sparse_count, element_size, false, problem);
  if (!values) return std::nullopt;
  for (std::size_t s = 0; s < sparse_count; ++s) {
    const auto target =
        decode_component<std::uint32_t>(indices->first + s * index_size, sparse.indices.componentType, false);
    if (target >= accessor.count) {
      problem = {sparse_where + "/indices", "index " + std::to_string(target) + " (sparse element " +
                                                std::to_string(s) + ") is not below the accessor's count " +
                                                std::to_string(accessor.count)};
      return std::nullopt;
    }
    decode_element(values->first + s * element_size, &out.values[target * per_element]);
  }
  return out;
}

}  // namespace

namespace {

std::optional<std::vector<std::uint32_t>> read_indices(const tinygltf::Model& model, const Asset* asset, int index,
                                                       AccessorProblem& problem) {
  if (index >= 0 && static_cast<std::size_t>(index) < model.accessors.size()) {
    const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
    if (accessor.type != TINYGLTF_TYPE_SCALAR || !is_unsigned_index_type(accessor.componentType)) {
      problem = {pointer("accessors", index), "indices are not SCALAR UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT"};
      return std::nullopt;
    }
  }
  auto indices = read_elements<std::uint32_t>(model, asset, index, problem);
  if (!indices) return std::nullopt;
  return std::move(indices->values);
}

}  // namespace

template <typename Number>
std::optional<AccessorValues<Number>> read_accessor(const tinygltf::Model& model, int index, AccessorProblem& problem) {
  static_assert(std::is_floating_point_v<Number>);
  return read_elements<Number>(model, nullptr, index, problem);
}
template std::optional<AccessorValues<float>> read_accessor(const tinygltf::Model&, int, AccessorProblem&);
template std::optional<AccessorValues<double>> read_accessor(const tinygltf::Model&, int, AccessorProblem&);

template <typename Number>
std::optional<AccessorValues<Number>> read_accessor(const Asset& asset, int index, AccessorProblem& problem) {
  static_assert(std::is_floating_point_v<Number>);
  return read_elements<Number>(asset.model, &asset, index, problem);
}
template std::optional<AccessorValues<float>> read_accessor(const Asset&, int, AccessorProblem&);
template std::optional<AccessorValues<double>> read_accessor(const Asset&, int, AccessorProblem&);

std::optional<std::vector<std::uint32_t>> read_index_accessor(const tinygltf::Model& model, int index,
                                                              AccessorProblem& problem) {
  return read_indices(model, nullptr, index, problem);
}

std::optional<std::vector<std::uint32_t>> read_index_accessor(const Asset& asset, int index, AccessorProblem& problem) {
  return read_indices(asset.model, &asset, index, problem);
}

AccessorValues<double> read_accessor_or_throw(const Asset& asset, int index) {
  AccessorProblem problem;
  auto values = read_accessor<double>(asset, index, problem);
  if (!values) throw InputError(asset.path.string(), problem.pointer, problem.reason);
  return std::move(*values);
}

std::vector<std::uint32_t> read_index_accessor_or_throw(const Asset& asset, int index) {
  AccessorProblem problem;
  auto indices = read_index_accessor(asset, index, problem);
  if (!indices) throw InputError(asset.path.string(), problem.pointer, problem.reason);
  return std::move(*indices);
}

std::optional<std::span<const std::uint8_t>> buffer_view_bytes(const Asset& asset, int index, std::string& problem) {
  AccessorProblem where;
  auto bytes = view_bytes(asset.model, &asset, index, pointer("bufferViews", index), where);
  if (!bytes) problem = where.text();
  return bytes;
}

DecodedViews& DecodedViews::operator=(const DecodedViews&) {
  const std::lock_guard lock(mutex_);
  views_.clear();
  decoded_bytes_ = 0;
  return *this;
}

const DecodedViews::Entry& DecodedViews::find_or_decode(
    int index, std::uint64_t decoded_size, std::uint64_t budget,
    const std::function<std::optional<std::vector<std::uint8_t>>(std::string&)>& decode) const {
  const std::lock_guard lock(mutex_);
  if (const auto found = views_.find(index); found != views_.end()) return found->second;
  Entry entry;
  entry.problem = meshopt_budget_problem(decoded_bytes_, decoded_size, budget);
  if (entry.problem.empty()) {
    entry.bytes = decode(entry.problem);
    if (entry.bytes) {
      decoded_bytes_ += entry.bytes->size();
      ++work_counters().views_decoded;
    }
  }
  return views_.emplace(index, std::move(entry)).first->second;
}

int append_buffer_view(tinygltf::Model& model, std::span<const std::uint8_t> bytes) {
  if (model.buffers.empty()) model.buffers.emplace_back();
  std::vector<unsigned char>& data = model.buffers[0].data;
  data.resize((data.size() + 3) & ~std::size_t{3}, 0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = bytes.size();
  data.insert(data.end(), bytes.begin(), bytes.end());
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size()) - 1;
}

int append_accessor(tinygltf::Model& model, std::span<const std::uint8_t> elements, int component_type, int type) {
  const std::size_t element_size =
      component_size(component_type) * static_cast<std::size_t>(tinygltf::GetNumComponentsInType(type));
  CHECK_LT(std::size_t{0}, element_size);
  CHECK_EQ(elements.size() % element_size, std::size_t{0});
  tinygltf::Accessor accessor;
  accessor.bufferView = append_buffer_view(model, elements);
  accessor.byteOffset = 0;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = elements.size() / element_size;
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size()) - 1;
}

}  // namespace gltf_pbr
