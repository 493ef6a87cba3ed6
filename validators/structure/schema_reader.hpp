// Typed property reads against the glTF 2.0 JSON schema (spec section 5 "Properties Reference"):
// each read reports TYPE_MISMATCH, UNDEFINED_PROPERTY, VALUE_NOT_IN_RANGE and the like at the
// property's JSON pointer, and returns the value only when it is valid.
#pragma once
#include <initializer_list>
#include <limits>

#include "validators/structure/structure_internal.hpp"

namespace gltf_pbr::structure {

struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool max_exclusive = false;
  bool contains(double value) const {
    if (!(value == value)) return false;
    if (min_exclusive ? value <= min : value < min) return false;
    if (max_exclusive ? value >= max : value > max) return false;
    return true;
  }
};

class SchemaReader {
 public:
  explicit SchemaReader(Context& context) : context_(context), issues_(context.issues) {}

  static std::string child(const std::string& pointer, std::string_view key) {
    return pointer + "/" + escape_pointer_token(key);
  }
  static std::string child(const std::string& pointer, std::size_t index) {
    return pointer + "/" + std::to_string(index);
  }

  // UNEXPECTED_PROPERTY for every key the schema does not name, in document order.
  void check_members(const Json& object, const std::string& pointer, std::initializer_list<std::string_view> known);

  std::int64_t index(const Json& object, const std::string& pointer, std::string_view key, bool required = false);
  std::optional<std::int64_t> integer(const Json& object, const std::string& pointer, std::string_view key,
                                      bool required = false, Range range = {},
                                      std::initializer_list<std::int64_t> allowed = {});
  std::optional<double> number(const Json& object, const std::string& pointer, std::string_view key,
                               bool required = false, Range range = {});
  std::optional<std::string> string(const Json& object, const std::string& pointer, std::string_view key,
                                    bool required = false, std::initializer_list<std::string_view> allowed = {});
  std::optional<bool> boolean(const Json& object, const std::string& pointer, std::string_view key);
  // A fixed-length (or any length when `lengths` is empty) array of numbers in `range`.
  std::optional<std::vector<double>> numbers(const Json& object, const std::string& pointer, std::string_view key,
                                             std::initializer_list<int> lengths = {}, Range range = {},
                                             bool required = false);
  std::optional<std::vector<std::int64_t>> indices(const Json& object, const std::string& pointer, std::string_view key,
                                                   bool required = false);
  const Json* object(const Json& object, const std::string& pointer, std::string_view key, bool required = false);
  // The array of objects under `key`. In a nested array a non-object is reported and the array
  // dropped; at the root, non-objects are given as nullptr (indices stay aligned with the
  // document's) for the caller to report in document order with element_not_object.
  std::optional<std::vector<const Json*>> object_array(const Json& object, const std::string& pointer,
                                                       std::string_view key, bool required, bool root_level);
  void extras(const Json& object, const std::string& pointer);
  void element_not_object(const Json& array, const std::string& pointer, std::size_t index) {
    issues_.at("TYPE_MISMATCH", child(pointer, index), {arg_json(array[index]), arg("object")});
  }

  // The array under `key`, or nullptr after reporting why not: absent (UNDEFINED_PROPERTY when required), not
  // an array (TYPE_MISMATCH) or empty (EMPTY_ENTITY); a required one in either case leaves its
  // object unusable. (A required scalar of the wrong type or value does not: the reference still
  // links its object.)
  const Json* non_empty_array(const Json& object, const std::string& pointer, std::string_view key, bool required);

  // UNDEFINED_PROPERTY, counted: an object that misses a required property is reported but not
  // linked or checked further (the reference drops it after its schema errors).
  void missing(const std::string& pointer, std::string_view key) {
    issues_.at("UNDEFINED_PROPERTY", pointer, {arg(key)});
    ++missing_count_;
  }
  std::size_t missing_count() const { return missing_count_; }
  void set_missing_count(std::size_t count) { missing_count_ = count; }

  IssueSink& issues() { return issues_; }
  Context& context() { return context_; }

 private:
  // The value under `key`, or nullptr when it is absent or null. A null is of no type: it is a
  // TYPE_MISMATCH against the `type` the schema wants, then counts as absent (a required property
  // is also UNDEFINED_PROPERTY), as in the reference.
  const Json* find(const Json& object, const std::string& pointer, std::string_view key, const char* type) {
    auto found = object.find(std::string(key));
    if (found == object.end()) return nullptr;
    if (found->is_null()) {
      issues_.at("TYPE_MISMATCH", child(pointer, key), {arg_json(*found), arg(type)});
      return nullptr;
    }
    return &*found;
  }
  // extras may hold any JSON value, null included.
  const Json* find(const Json& object, std::string_view key) const {
    auto found = object.find(std::string(key));
    return found == object.end() || found->is_null() ? nullptr : &*found;
  }
  Context& context_;
  IssueSink& issues_;
  std::size_t missing_count_ = 0;
};

// integer_value (core/json.hpp): a JSON integer as the schema counts one, saturated to int64.
inline bool is_integer(const Json& value) { return integer_value(value).has_value(); }

// Whether `object` defines `key` (a null value does not, as in the reference's Dart maps).
inline bool present(const Json& object, std::string_view key) {
  auto found = object.find(std::string(key));
  return found != object.end() && !found->is_null();
}

}  // namespace gltf_pbr::structure
