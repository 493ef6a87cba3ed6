#include "validators/structure/schema_reader.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace gltf_pbr::structure {

void SchemaReader::check_members(const Json& object, const std::string& pointer,
                                 std::initializer_list<std::string_view> known) {
  for (const auto& [key, value] : object.items()) {
    if (std::find(known.begin(), known.end(), key) == known.end())
      issues_.at("UNEXPECTED_PROPERTY", child(pointer, key));
  }
}

std::int64_t SchemaReader::index(const Json& object, const std::string& pointer, std::string_view key, bool required) {
  const Json* value = find(object, pointer, key, "integer");
  if (!value) {
    if (required) missing(pointer, key);
    return -1;
  }
  const std::optional<std::int64_t> integer = integer_value(*value);
  if (!integer) {
    issues_.at("TYPE_MISMATCH", child(pointer, key), {arg_json(*value), arg("integer")});
    return -1;
  }
  const std::int64_t number = *integer;
  if (number < 0) {
    issues_.at("INVALID_INDEX", child(pointer, key));
    return -1;
  }
  return number;
}

std::optional<std::int64_t> SchemaReader::integer(const Json& object, const std::string& pointer, std::string_view key,
                                                  bool required, Range range,
                                                  std::initializer_list<std::int64_t> allowed) {
  const Json* value = find(object, pointer, key, "integer");
  if (!value) {
    if (required) missing(pointer, key);
    return std::nullopt;
  }
  const std::optional<std::int64_t> integer = integer_value(*value);
  if (!integer) {
    issues_.at("TYPE_MISMATCH", child(pointer, key), {arg_json(*value), arg("integer")});
    return std::nullopt;
  }
  const std::int64_t number = *integer;
  if (allowed.size() > 0) {
    if (std::find(allowed.begin(), allowed.end(), number) == allowed.end()) {
      std::vector<MessageArg> list;
      for (auto item : allowed) list.push_back(arg(item));
      issues_.at("VALUE_NOT_IN_LIST", child(pointer, key), {arg(number)}, list);  // a warning: still usable
      return std::nullopt;
    }
  } else if (!range.contains(static_cast<double>(number))) {
    issues_.at("VALUE_NOT_IN_RANGE", child(pointer, key), {arg(number)});
    return std::nullopt;
  }
  return number;
}

std::optional<double> SchemaReader::number(const Json& object, const std::string& pointer, std::string_view key,
                                           bool required, Range range) {
  const Json* value = find(object, pointer, key, "number");
  if (!value) {
    if (required) missing(pointer, key);
    return std::nullopt;
  }
  if (!value->is_number()) {
    issues_.at("TYPE_MISMATCH", child(pointer, key), {arg_json(*value), arg("number")});
    return std::nullopt;
  }
  const double number = value->get<double>();
  if (!std::isfinite(number) || !range.contains(number)) {
    issues_.at("VALUE_NOT_IN_RANGE", child(pointer, key),
               {value->is_number_float() ? arg_double(number) : arg_raw(value->dump())});
    return std::nullopt;
  }
  return number;
}

std::optional<std::string> SchemaReader::string(const Json& object, const std::string& pointer, std::string_view key,
                                                bool required, std::initializer_list<std::string_view> allowed) {
  const Json* value = find(object, pointer, key, "string");
  if (!value) {
    if (required) missing(pointer, key);
    return std::nullopt;
  }
  if (!value->is_string()) {
    issues_.at("TYPE_MISMATCH", child(pointer, key), {arg_json(*value), arg("string")});
    return std::nullopt;
  }
  std::string text = value->get<std::string>();
  if (allowed.size() > 0 && std::find(allowed.begin(), allowed.end(), text) == allowed.end()) {
    std::vector<MessageArg> list;
    for (auto item : allowed) list.push_back(arg(item));
    issues_.at("VALUE_NOT_IN_LIST", child(pointer, key), {arg(text)}, list);  // a warning: still usable
    return std::nullopt;
  }
  return text;
}

std::optional<bool> SchemaReader::boolean(const Json& object, const std::string& pointer, std::string_view key) {
  const Json* value = find(object, pointer, key, "boolean");
  if (!value) return std::nullopt;
  if (!value->is_boolean()) {
    issues_.at("TYPE_MISMATCH", child(pointer, key), {arg_json(*value), arg("boolean")});
    return std::nullopt;
  }
  return value->get<bool>();
}

const Json* SchemaReader::non_empty_array(const Json& object, const std::string& pointer, std::string_view key,
                                          bool required) {
  const Json* value = find(object, pointer, key, "array");
  if (!value) {
    if (required) missing(pointer, key);
    return nullptr;
  }
  const std::string here = child(pointer, key);
  // A required array that is not one, or is empty, leaves its object unusable (the reference does
  // not link it), unlike a wrong scalar.
  if (!value->is_array()) {
    issues_.at("TYPE_MISMATCH", here, {arg_json(*value), arg("array")});
    if (required) ++missing_count_;
    return nullptr;
  }
  if (value->empty()) {
    issues_.at("EMPTY_ENTITY", here);
    if (required) ++missing_count_;
    return nullptr;
  }
  return value;
}

std::optional<std::vector<double>> SchemaReader::numbers(const Json& object, const std::string& pointer,
                                                         std::string_view key, std::initializer_list<int> lengths,
                                                         Range range, bool required) {
  const Json* value = non_empty_array(object, pointer, key, required);
  if (!value) return std::nullopt;
  const std::string here = child(pointer, key);
  if (lengths.size() > 0 &&
      std::find(lengths.begin(), lengths.end(), static_cast<int>(std::min<std::size_t>(value->size(), 1u << 30))) ==
          lengths.end()) {
    std::vector<MessageArg> list;
    for (int length : lengths) list.push_back(arg(length));
    issues_.at("ARRAY_LENGTH_NOT_IN_LIST", here, {arg(static_cast<std::uint64_t>(value->size()))}, list);
    return std::nullopt;
  }
  std::vector<double> result;
  result.reserve(value->size());
  bool valid = true;
  for (std::size_t i = 0; i < value->size(); ++i) {
    const Json& item = (*value)[i];
    if (!item.is_number()) {
      issues_.at("ARRAY_TYPE_MISMATCH", here, {arg_json(item), arg("number")});  // the reference names the array
      valid = false;
      continue;
    }
    const double number = item.get<double>();
    if (!std::isfinite(number) || !range.contains(number)) {
      issues_.at("VALUE_NOT_IN_RANGE", child(here, i),
                 {item.is_number_float() ? arg_double(number) : arg_raw(item.dump())});
      valid = false;
    }
    result.push_back(number);
  }
  if (!valid) return std::nullopt;
  return result;
}

std::optional<std::vector<std::int64_t>> SchemaReader::indices(const Json& object, const std::string& pointer,
                                                               std::string_view key, bool required) {
  const Json* value = non_empty_array(object, pointer, key, required);
  if (!value) return std::nullopt;
  const std::string here = child(pointer, key);
  std::vector<std::int64_t> result;
  std::set<std::int64_t> seen;
  for (std::size_t i = 0; i < value->size(); ++i) {
    const Json& item = (*value)[i];
    // Anything but a non-negative integer is an invalid index, whatever its type.
    const std::int64_t number = integer_value(item).value_or(-1);
    if (number < 0) {
      issues_.at("INVALID_INDEX", child(here, i));
      result.push_back(-1);
      continue;
    }
    if (!seen.insert(number).second) issues_.at("DUPLICATE_ELEMENTS", child(here, i));
    result.push_back(number);
  }
  return result;
}

const Json* SchemaReader::object(const Json& object, const std::string& pointer, std::string_view key, bool required) {
  const Json* value = find(object, pointer, key, "object");
  if (!value) {
    if (required) missing(pointer, key);
    return nullptr;
  }
  if (!value->is_object()) {
    issues_.at("TYPE_MISMATCH", child(pointer, key), {arg_json(*value), arg("object")});
    return nullptr;
  }
  return value;
}

std::optional<std::vector<const Json*>> SchemaReader::object_array(const Json& object, const std::string& pointer,
                                                                   std::string_view key, bool required,
                                                                   bool root_level) {
  const Json* value = non_empty_array(object, pointer, key, required);
  if (!value) return std::nullopt;
  const std::string here = child(pointer, key);
  std::vector<const Json*> result;
  result.reserve(value->size());
  bool all_objects = true;
  for (std::size_t i = 0; i < value->size(); ++i) {
    const Json& item = (*value)[i];
    if (item.is_object()) {
      result.push_back(&item);
      continue;
    }
    // Top-level collections keep the other elements (the caller names this one in turn, see
    // element_not_object); a nested array names itself and is dropped whole, as if absent
    // (the reference reads none of its elements then).
    all_objects = false;
    if (!root_level) issues_.at("ARRAY_TYPE_MISMATCH", here, {arg_json(item), arg("object")});
    result.push_back(nullptr);
  }
  if (!root_level && !all_objects) {
    if (required) ++missing_count_;  // a required property that is unusable counts as missing
    return std::nullopt;
  }
  return result;
}

void SchemaReader::extras(const Json& object, const std::string& pointer) {
  const Json* value = find(object, "extras");
  if (value && !value->is_object()) issues_.at("NON_OBJECT_EXTRAS", child(pointer, "extras"));
}

}  // namespace gltf_pbr::structure
