// The GLB container (glTF 2.0 spec, section 4.4 "Binary glTF Layout") and the JSON parse. GLB
// issues carry byte offsets instead of pointers: the offset of the header field or chunk header at
// fault, or the stream position where reading stopped.
#include <cstdio>

#include "core/byte_order.hpp"
#include "core/glb.hpp"
#include "core/json.hpp"
#include "validators/structure/structure_internal.hpp"

namespace gltf_pbr::structure {

namespace {
std::string hex32(std::uint32_t value) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08x", value);
  return text;
}
}  // namespace

std::optional<std::span<const std::uint8_t>> read_glb(std::span<const std::uint8_t> bytes, Context& context,
                                                      bool& empty_json_ended) {
  IssueSink& issues = context.issues;
  empty_json_ended = false;
  if (bytes.size() >= 4 && little_endian32(bytes, 0) != kGlbMagic) {
    issues.at_offset("GLB_INVALID_MAGIC", 0, {arg(static_cast<std::uint64_t>(little_endian32(bytes, 0)))});
    return std::nullopt;
  }
  if (bytes.size() < 12) {
    issues.at_offset("GLB_UNEXPECTED_END_OF_HEADER", bytes.size());
    return std::nullopt;
  }
  const std::uint32_t version = little_endian32(bytes, 4);
  if (version != 2) {
    // Another container version has another layout (glTF 1.0's binary extension): stop here.
    issues.at_offset("GLB_INVALID_VERSION", 4, {arg(static_cast<std::uint64_t>(version))});
    return std::nullopt;
  }
  const std::uint64_t declared_length = little_endian32(bytes, 8);
  if (declared_length < 12) issues.at_offset("GLB_LENGTH_TOO_SMALL", 8, {arg(declared_length)});

  std::optional<std::span<const std::uint8_t>> json;
  bool json_seen = false, bin_seen = false, json_was_empty = false;
  int chunk_index = 0;
  // Chunks are read until they end exactly at the declared length or the stream ends, so a length
  // declared too small (GLB_LENGTH_TOO_SMALL, or one a chunk steps over) is measured against every
  // chunk there is (GLB_CHUNK_TOO_BIG each) and the real end (GLB_LENGTH_MISMATCH).
  GlbChunks chunks(bytes, declared_length);
  while (!chunks.done()) {
    // An empty JSON chunk leaves the JSON text open until something follows it; then it is parsed
    // as the empty text it is (INVALID_JSON), as the reference does (checked against the npm build).
    if (json_seen && json_was_empty) empty_json_ended = true;
    const std::optional<GlbChunk> chunk = chunks.next();
    if (!chunk) {
      context.glb_end_issues.push_back({"GLB_UNEXPECTED_END_OF_CHUNK_HEADER", bytes.size(), {}});
      context.glb_ended_inside_chunk = true;
      return json;
    }
    const std::uint64_t chunk_start = chunk->offset;
    const std::uint64_t chunk_length = chunk->length;
    const std::uint32_t chunk_type = chunk->type;
    if (chunk_length % 4 != 0)
      issues.at_offset("GLB_CHUNK_LENGTH_UNALIGNED", chunk_start, {arg_raw(hex32(chunk_type))});
    if (chunk->end() > declared_length)
      issues.at_offset("GLB_CHUNK_TOO_BIG", chunk_start, {arg_raw(hex32(chunk_type)), arg(chunk_length)});
    if (chunk_type == kGlbChunkJson) {
      if (chunk_length == 0) issues.at_offset("GLB_EMPTY_CHUNK", chunk_start, {arg_raw(hex32(chunk_type))});
      if (json_seen) issues.at_offset("GLB_DUPLICATE_CHUNK", chunk_start, {arg_raw(hex32(chunk_type))});
    } else if (chunk_type == kGlbChunkBin) {
      context.glb_bin_chunk = true;
      if (chunk_index == 0)
        issues.at_offset("GLB_UNEXPECTED_FIRST_CHUNK", chunk_start, {arg_raw(hex32(chunk_type))});
      else if (chunk_index != 1 && !bin_seen)
        issues.at_offset("GLB_UNEXPECTED_BIN_CHUNK", chunk_start);
      if (chunk_length == 0) issues.at_offset("GLB_EMPTY_BIN_CHUNK", chunk_start);
      if (bin_seen) issues.at_offset("GLB_DUPLICATE_CHUNK", chunk_start, {arg_raw(hex32(chunk_type))});
    } else {
      if (chunk_index == 0) issues.at_offset("GLB_UNEXPECTED_FIRST_CHUNK", chunk_start, {arg_raw(hex32(chunk_type))});
      issues.at_offset("GLB_UNKNOWN_CHUNK_TYPE", chunk_start, {arg_raw(hex32(chunk_type))});
    }
    if (!chunk->whole()) {
      context.glb_end_issues.push_back({"GLB_UNEXPECTED_END_OF_CHUNK_DATA", bytes.size(), {}});
      context.glb_ended_inside_chunk = true;
      return json;
    }
    if (chunk_type == kGlbChunkJson && !json_seen) {
      json_seen = true;
      json_was_empty = chunk_length == 0;
      if (chunk_length > 0) json = chunk->data;
    } else if (chunk_type == kGlbChunkBin && !bin_seen) {
      bin_seen = true;
      context.glb_bin = chunk->data;
    }
    ++chunk_index;
  }
  const std::uint64_t offset = chunks.position();
  if (offset != declared_length) {
    context.glb_end_issues.push_back({"GLB_LENGTH_MISMATCH", offset, {arg(declared_length), arg(offset)}});
  } else if (bytes.size() > offset) {
    context.glb_end_issues.push_back({"GLB_EXTRA_DATA", offset, {}});
  }
  return json;
}

bool parse_json(std::span<const std::uint8_t> text, Context& context) {
  // RFC 8259 8.1 forbids a byte order mark; the reference reports it and reads on.
  if (text.size() >= 3 && text[0] == 0xEF && text[1] == 0xBB && text[2] == 0xBF) {
    context.issues.at("INVALID_JSON", "", {arg_raw("BOM found at the beginning of UTF-8 stream.")});
    text = text.subspan(3);
  }
  // The reference decodes UTF-8 strictly before it parses (RFC 8259 8.1: JSON text is UTF-8).
  if (const std::optional<JsonProblem> problem = read_json(text, context.root, &context.json_flaws)) {
    const char* what = problem->kind == JsonProblem::Kind::InvalidUtf8           ? "Invalid UTF-8 byte"
                       : problem->kind == JsonProblem::Kind::UnexpectedCharacter ? "Unexpected character"
                       : problem->kind == JsonProblem::Kind::UnexpectedEnd       ? "Unexpected end of input"
                                                                                 : "Nesting too deep";
    context.issues.at(
        "INVALID_JSON", "",
        {arg_raw(std::string("FormatException: ") + what + " (at offset " + std::to_string(problem->offset) + ")")});
    return false;
  }
  if (!context.root.is_object()) {
    context.issues.at("TYPE_MISMATCH", "", {arg_json(context.root), arg("object")});
    return false;
  }
  return true;
}

}  // namespace gltf_pbr::structure
