#include "core/meshopt.hpp"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>

namespace gltf_pbr {

std::optional<MeshoptMode> meshopt_mode(std::string_view name) {
  if (name == "ATTRIBUTES") return MeshoptMode::Attributes;
  if (name == "TRIANGLES") return MeshoptMode::Triangles;
  if (name == "INDICES") return MeshoptMode::Indices;
  return std::nullopt;
}

std::optional<MeshoptFilter> meshopt_filter(std::string_view name) {
  if (name == "NONE") return MeshoptFilter::None;
  if (name == "OCTAHEDRAL") return MeshoptFilter::Octahedral;
  if (name == "QUATERNION") return MeshoptFilter::Quaternion;
  if (name == "EXPONENTIAL") return MeshoptFilter::Exponential;
  return std::nullopt;
}

std::string meshopt_layout_problem(const MeshoptView& view, std::uint64_t parent_byte_length,
                                   std::uint64_t parent_byte_stride) {
  const std::uint64_t stride = view.byte_stride;
  if (parent_byte_stride != 0 && parent_byte_stride != stride)
    return "the bufferView's byteStride " + std::to_string(parent_byte_stride) + " differs from the extension's " +
           std::to_string(stride);
  if (stride == 0 || view.count > parent_byte_length / stride || view.count * stride != parent_byte_length)
    return "the bufferView's byteLength " + std::to_string(parent_byte_length) + " is not byteStride " +
           std::to_string(stride) + " times count " + std::to_string(view.count);
  switch (view.mode) {
    case MeshoptMode::Attributes:
      if (stride % 4 != 0 || stride > 256) return "ATTRIBUTES needs a byteStride divisible by 4 and at most 256, not " +
                                                  std::to_string(stride);
      break;
    case MeshoptMode::Triangles:
      if (view.count % 3 != 0) return "TRIANGLES needs a count divisible by 3, not " + std::to_string(view.count);
      [[fallthrough]];
    case MeshoptMode::Indices:
      if (stride != 2 && stride != 4) return "TRIANGLES and INDICES need a byteStride of 2 or 4, not " +
                                             std::to_string(stride);
      if (view.filter != MeshoptFilter::None) return "TRIANGLES and INDICES take no filter";
      break;
  }
  if (view.filter == MeshoptFilter::Octahedral && stride != 4 && stride != 8)
    return "OCTAHEDRAL needs a byteStride of 4 or 8, not " + std::to_string(stride);
  if (view.filter == MeshoptFilter::Quaternion && stride != 8)
    return "QUATERNION needs a byteStride of 8, not " + std::to_string(stride);
  if (view.filter == MeshoptFilter::Exponential && stride % 4 != 0)
    return "EXPONENTIAL needs a byteStride divisible by 4, not " + std::to_string(stride);
  return {};
}

namespace {

// The fewest compressed bytes that can hold `count` elements (the extension's Appendix A): an
// attribute stream spends at least 2 header bits per 16 elements on each byte of the element, a
// triangle stream one code byte per triangle, an index sequence at least one byte per index.
// Anything shorter cannot decode, so it is refused before the output is allocated.
std::uint64_t fewest_compressed_bytes(const MeshoptView& view) {
  switch (view.mode) {
    case MeshoptMode::Attributes:
      return view.byte_stride * ((view.count + 63) / 64);
    case MeshoptMode::Triangles:
      return view.count / 3;
    case MeshoptMode::Indices:
      return view.count;
  }
  return 0;
}

}  // namespace

std::optional<std::vector<std::uint8_t>> decode_meshopt(std::span<const std::uint8_t> compressed,
                                                        const MeshoptView& view, std::string& problem) {
  if (view.byte_stride == 0 || view.count > UINT64_MAX / view.byte_stride) {
    problem = "byteStride " + std::to_string(view.byte_stride) + " times count " + std::to_string(view.count) +
              " is no size";
    return std::nullopt;
  }
  problem = meshopt_layout_problem(view, view.count * view.byte_stride, 0);
  if (!problem.empty()) return std::nullopt;
  if (compressed.size() < fewest_compressed_bytes(view)) {
    problem = std::to_string(compressed.size()) + " compressed bytes cannot hold " + std::to_string(view.count) +
              " elements of " + std::to_string(view.byte_stride) + " bytes";
    return std::nullopt;
  }
  std::vector<std::uint8_t> decoded(view.count * view.byte_stride);
  const auto count = static_cast<std::size_t>(view.count);
  const auto stride = static_cast<std::size_t>(view.byte_stride);
  int status = 0;
  switch (view.mode) {
    case MeshoptMode::Attributes:
      status = meshopt_decodeVertexBuffer(decoded.data(), count, stride, compressed.data(), compressed.size());
      break;
    case MeshoptMode::Triangles:
      status = meshopt_decodeIndexBuffer(decoded.data(), count, stride, compressed.data(), compressed.size());
      break;
    case MeshoptMode::Indices:
      status = meshopt_decodeIndexSequence(decoded.data(), count, stride, compressed.data(), compressed.size());
      break;
  }
  if (status != 0) {
    // meshoptimizer's codes: -1 an unknown header (another codec version), -2 too few bytes,
    // -3 bytes left over.
    problem = status == -1   ? "the compressed bytes do not start with a known codec header"
              : status == -2 ? "the compressed bytes end before " + std::to_string(view.count) + " elements decode"
              : status == -3 ? "bytes are left over after " + std::to_string(view.count) + " elements decode"
                             : "meshoptimizer refused the compressed bytes (status " + std::to_string(status) + ")";
    return std::nullopt;
  }
  // Appendix B: each filter transforms the decoded elements in place.
  switch (view.filter) {
    case MeshoptFilter::None:
      break;
    case MeshoptFilter::Octahedral:
      meshopt_decodeFilterOct(decoded.data(), count, stride);
      break;
    case MeshoptFilter::Quaternion:
      meshopt_decodeFilterQuat(decoded.data(), count, stride);
      break;
    case MeshoptFilter::Exponential:
      meshopt_decodeFilterExp(decoded.data(), count, stride);
      break;
  }
  return decoded;
}

std::uint64_t meshopt_decode_budget(std::uint64_t stored_bytes) {
  constexpr std::uint64_t kExpansion = 64, kSlack = std::uint64_t{1} << 20;
  return stored_bytes > (UINT64_MAX - kSlack) / kExpansion ? UINT64_MAX : stored_bytes * kExpansion + kSlack;
}

std::string meshopt_budget_problem(std::uint64_t decoded, std::uint64_t size, std::uint64_t budget) {
  if (size <= budget && decoded <= budget - size) return {};
  return "decoding it would take the file's decoded views past " + std::to_string(budget) +
         " bytes, 64 times the data it stores";
}

namespace {

// The two documents' values, seen alike by the one reader below: tinygltf's (the Asset every
// step reads) and our JSON tree's (the loader's pre-pass and the structure step).
const tinygltf::Value* member(const tinygltf::Value& object, const char* name) {
  return object.IsObject() && object.Has(name) ? &object.Get(name) : nullptr;
}
const JsonDocument* member(const JsonDocument& object, const char* name) {
  if (!object.is_object()) return nullptr;
  const auto found = object.find(name);
  return found == object.end() ? nullptr : &*found;
}
bool is_object(const tinygltf::Value& value) { return value.IsObject(); }
bool is_object(const JsonDocument& value) { return value.is_object(); }
// An integer as the schema counts one (core/json.hpp integer_value: 4 and 4.0 alike), saturated
// to int64. tinygltf holds an int or a double.
std::optional<std::int64_t> integer_of(const JsonDocument& value) { return integer_value(value); }
std::optional<std::int64_t> integer_of(const tinygltf::Value& value) {
  if (value.IsInt()) return value.Get<int>();
  return value.IsNumber() ? integer_value(JsonDocument(value.GetNumberAsDouble())) : std::nullopt;
}
std::optional<std::string> string_of(const tinygltf::Value& value) {
  return value.IsString() ? std::optional(value.Get<std::string>()) : std::nullopt;
}
std::optional<std::string> string_of(const JsonDocument& value) {
  return value.is_string() ? std::optional(value.get<std::string>()) : std::nullopt;
}
std::optional<bool> boolean_of(const tinygltf::Value& value) {
  return value.IsBool() ? std::optional(value.Get<bool>()) : std::nullopt;
}
std::optional<bool> boolean_of(const JsonDocument& value) {
  return value.is_boolean() ? std::optional(value.get<bool>()) : std::nullopt;
}

template <class Value>
std::optional<std::uint64_t> unsigned_member(const Value& object, const char* name) {
  const Value* value = member(object, name);
  const std::optional<std::int64_t> integer = value ? integer_of(*value) : std::nullopt;
  if (!integer || *integer < 0) return std::nullopt;
  return static_cast<std::uint64_t>(*integer);
}

// The bufferView extension object (the extension's README, "bufferView properties").
template <class Value>
std::optional<MeshoptView> read_view(const Value& object, std::string& problem) {
  problem.clear();
  if (!is_object(object)) {
    problem = "the extension is not an object";
    return std::nullopt;
  }
  const auto buffer = unsigned_member(object, "buffer");
  const auto byte_length = unsigned_member(object, "byteLength");
  const auto byte_stride = unsigned_member(object, "byteStride");
  const auto count = unsigned_member(object, "count");
  for (const auto& [name, value] : {std::pair{"buffer", buffer}, std::pair{"byteLength", byte_length},
                                    std::pair{"byteStride", byte_stride}, std::pair{"count", count}}) {
    if (!value) {
      problem = std::string(name) + " is missing or not a non-negative integer";
      return std::nullopt;
    }
  }
  const Value* mode_value = member(object, "mode");
  const std::optional<std::string> mode_name = mode_value ? string_of(*mode_value) : std::nullopt;
  const std::optional<MeshoptMode> mode = mode_name ? meshopt_mode(*mode_name) : std::nullopt;
  if (!mode) {
    problem = "mode is not ATTRIBUTES, TRIANGLES or INDICES";
    return std::nullopt;
  }
  std::optional<MeshoptFilter> filter = MeshoptFilter::None;
  if (const Value* filter_value = member(object, "filter")) {
    const std::optional<std::string> name = string_of(*filter_value);
    filter = name ? meshopt_filter(*name) : std::nullopt;
  }
  if (!filter) {
    problem = "filter is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL";
    return std::nullopt;
  }
  const auto byte_offset = member(object, "byteOffset") ? unsigned_member(object, "byteOffset") : std::uint64_t{0};
  if (!byte_offset) {
    problem = "byteOffset is not a non-negative integer";
    return std::nullopt;
  }
  MeshoptView out;
  out.buffer = static_cast<std::int64_t>(*buffer);
  out.byte_offset = *byte_offset;
  out.byte_length = *byte_length;
  out.byte_stride = *byte_stride;
  out.count = *count;
  out.mode = *mode;
  out.filter = *filter;
  return out;
}

// The buffer extension object: {"fallback": true} ("Fallback buffers").
template <class Value>
bool fallback_of(const Value& extension) {
  const Value* fallback = member(extension, "fallback");
  return fallback && boolean_of(*fallback).value_or(false);
}

}  // namespace

std::optional<MeshoptView> meshopt_view(const tinygltf::BufferView& view, std::string& problem) {
  problem.clear();
  const auto found = view.extensions.find("EXT_meshopt_compression");
  if (found == view.extensions.end()) return std::nullopt;
  return read_view(found->second, problem);
}

std::optional<MeshoptView> meshopt_view_from_json(const JsonDocument& extension, std::string& problem) {
  return read_view(extension, problem);
}

bool is_meshopt_fallback(const tinygltf::Buffer& buffer) {
  const auto found = buffer.extensions.find("EXT_meshopt_compression");
  return found != buffer.extensions.end() && fallback_of(found->second);
}

bool is_meshopt_fallback_json(const JsonDocument& buffer) {
  const JsonDocument* extensions = member(buffer, "extensions");
  const JsonDocument* extension = extensions ? member(*extensions, "EXT_meshopt_compression") : nullptr;
  return extension && fallback_of(*extension);
}

bool is_meshopt_placeholder(const tinygltf::Buffer& buffer) {
  return is_meshopt_fallback(buffer) && buffer.uri.empty() && buffer.data.empty();
}

std::optional<std::uint64_t> meshopt_source_buffer(const tinygltf::BufferView& view) {
  const auto found = view.extensions.find("EXT_meshopt_compression");
  if (found == view.extensions.end() || !found->second.IsObject()) return std::nullopt;
  return unsigned_member(found->second, "buffer");
}

void set_meshopt_source_buffer(tinygltf::BufferView& view, int buffer) {
  const auto found = view.extensions.find("EXT_meshopt_compression");
  if (found == view.extensions.end() || !found->second.IsObject()) return;
  tinygltf::Value::Object object = found->second.Get<tinygltf::Value::Object>();
  object["buffer"] = tinygltf::Value(buffer);
  found->second = tinygltf::Value(std::move(object));
}

void set_meshopt_source(tinygltf::BufferView& view, int buffer, std::uint64_t byte_offset) {
  const auto found = view.extensions.find("EXT_meshopt_compression");
  if (found == view.extensions.end() || !found->second.IsObject()) return;
  tinygltf::Value::Object object = found->second.Get<tinygltf::Value::Object>();
  object["buffer"] = tinygltf::Value(buffer);
  // An int where it fits: tinygltf writes a double with a fraction part ("24516.0").
  object["byteOffset"] = byte_offset <= INT32_MAX ? tinygltf::Value(static_cast<int>(byte_offset))
                                                  : tinygltf::Value(static_cast<double>(byte_offset));
  found->second = tinygltf::Value(std::move(object));
}

}  // namespace gltf_pbr
