// The one JSON reader of a glTF document (RFC 8259). The structure step reports from its tree, and
// the loader checks and prepares the same tree for the document library, so a file's JSON is read
// one way, and once when both run (core/resources.hpp keeps the tree between them).
#pragma once
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>

namespace gltf_pbr {

// Objects keep their keys in the order written: reports list members as the file does.
using JsonDocument = nlohmann::ordered_json;

// glTF needs a few levels of nesting and extras may use more; a hostile file nested 100 000 deep
// would exhaust the stack of any recursive reader, this one's and the document library's.
constexpr int kMaxJsonDepth = 512;

struct JsonProblem {
  enum class Kind {
    InvalidUtf8,          // RFC 8259 section 8.1: JSON text is UTF-8
    UnexpectedCharacter,  // the grammar of RFC 8259 sections 2-7
    UnexpectedEnd,
    TooDeep,  // nesting deeper than kMaxJsonDepth
  };
  Kind kind;
  std::size_t offset;  // in the text given
};

// Reads `text` as the Khronos validator's Dart reader does: strict UTF-8 first, then the grammar;
// integers stay integers (int64, or uint64 above its range), a number beyond a double's range
// becomes an infinity (Dart reads 1e309 as Infinity; first_non_finite_number finds it for a step
// that must refuse it; `first_non_finite` receives the first such number as written), and a
// repeated key keeps its first position with its last value. A byte order mark is the caller's to
// skip or report.
std::optional<JsonProblem> read_json(std::span<const std::uint8_t> text, JsonDocument& out,
                                     std::string* first_non_finite = nullptr);

// The JSON pointer (RFC 6901) of the first number in `value` that is not finite, if any.
std::optional<std::string> first_non_finite_number(const JsonDocument& value);

}  // namespace gltf_pbr
