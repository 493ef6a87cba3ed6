// Message text: the catalogue's templates (rules/structure.json, copied from the reference's
// ISSUES.md) filled the way the reference prints values. The reference runs on the Dart VM, so an
// integral double prints as "1.0", infinities as "Infinity" and strings quoted as 'text'.
#include <charconv>
#include <cmath>

#include "core/error.hpp"
#include "validators/structure/structure_internal.hpp"

namespace gltf_pbr::structure {

std::string format_double(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "Infinity" : "-Infinity";
  if (value == std::floor(value) && std::fabs(value) < 1e21) {
    char buffer[64];
    auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, 1);
    return std::string(buffer, result.ptr);
  }
  char buffer[64];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);  // shortest round trip, as Dart
  return std::string(buffer, result.ptr);
}

MessageArg arg(std::string_view text) { return {std::string(text), true}; }
MessageArg arg(std::int64_t value) { return {std::to_string(value), false}; }
MessageArg arg(std::uint64_t value) { return {std::to_string(value), false}; }
MessageArg arg(int value) { return {std::to_string(value), false}; }
MessageArg arg_double(double value) { return {format_double(value), false}; }
MessageArg arg_raw(std::string text) { return {std::move(text), false}; }

namespace {
std::string json_text(const Json& value) {
  switch (value.type()) {
    case Json::value_t::string:
      return "'" + value.get<std::string>() + "'";
    case Json::value_t::number_float:
      return format_double(value.get<double>());
    case Json::value_t::array: {
      std::string text = "[";
      for (std::size_t i = 0; i < value.size(); ++i) text += (i ? ", " : "") + json_text(value[i]);
      return text + "]";
    }
    case Json::value_t::object: {
      std::string text = "{";
      bool first = true;
      for (const auto& [key, item] : value.items()) {
        text += (first ? "" : ", ") + key + ": " + json_text(item);
        first = false;
      }
      return text + "}";
    }
    default:
      return value.dump();
  }
}

}  // namespace

MessageArg arg_json(const Json& value) { return {json_text(value), false}; }

bool Context::declared(std::string_view extension) const {
  for (const auto& name : doc.extensions_used)
    if (name == extension) return true;
  return false;
}

int component_size(int component_type) {
  switch (component_type) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    case 5125:
    case 5126:
      return 4;
    default:
      return 0;
  }
}

int component_count(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4" || type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

const char* component_type_name(int component_type) {
  switch (component_type) {
    case 5120:
      return "BYTE";
    case 5121:
      return "UNSIGNED_BYTE";
    case 5122:
      return "SHORT";
    case 5123:
      return "UNSIGNED_SHORT";
    case 5125:
      return "UNSIGNED_INT";
    case 5126:
      return "FLOAT";
    default:
      return "UNKNOWN";
  }
}

}  // namespace gltf_pbr::structure
