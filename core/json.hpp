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

// What the reader kept that a document library cannot hold (first_flaw finds where): a step that
// must refuse such values walks the tree only when the reader saw one.
struct JsonFlawsSeen {
  bool lone_surrogate = false;
  std::string first_non_finite;  // the first number beyond a double's range, as written
  bool any() const { return lone_surrogate || !first_non_finite.empty(); }
};

// Reads `text` as the Khronos validator's Dart reader does: strict UTF-8 first, then the grammar.
// Integers stay integers (int64, or uint64 above its range). A number beyond a double's range
// becomes an infinity, as Dart reads 1e309 as Infinity. A lone surrogate escape ("\uD800", which
// RFC 8259 section 8.2 leaves to the reader) is kept as its three bytes. Both are noted in `seen`.
// A repeated key keeps its first position with its last value. A byte order mark is the caller's
// to skip or report.
std::optional<JsonProblem> read_json(std::span<const std::uint8_t> text, JsonDocument& out,
                                     JsonFlawsSeen* seen = nullptr);

// A value that the reader keeps but a document library cannot hold, and where it is.
struct JsonFlaw {
  enum class Kind {
    NonFiniteNumber,  // JSON numbers are finite (RFC 8259 section 6); 1e999 overflows a double
    NotUnicode,       // a string or key holding a lone surrogate
  };
  Kind kind;
  std::string pointer;  // RFC 6901
};
// The first flaw in `value`, in document order, if any.
std::optional<JsonFlaw> first_flaw(const JsonDocument& value);

// The value of a JSON integer, saturated to the int64 range; std::nullopt when `value` is not one.
// JSON Schema (2020-12 validation 6.1.1, the glTF schema's draft) counts any number with a zero
// fractional part as an integer, so 1, 1.0 and 1e0 are the same index (the npm reference agrees).
std::optional<std::int64_t> integer_value(const JsonDocument& value);

}  // namespace gltf_pbr
