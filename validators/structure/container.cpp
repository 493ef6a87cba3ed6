// The GLB container (glTF 2.0 spec, section 4.4 "Binary glTF Layout") and the JSON parse. GLB
// issues carry byte offsets instead of pointers: the offset of the header field or chunk header at
// fault, or the stream position where reading stopped.
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "core/byte_order.hpp"
#include "core/glb.hpp"
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

namespace {

// A JSON parser (RFC 8259) that reads as the reference's Dart parser does: integers stay integers,
// numbers beyond double range become infinities (Dart parses 1e309 as Infinity, where nlohmann's
// parser throws), a repeated key keeps its first position with the last value, and errors name the
// byte offset. Nesting is bounded so that hostile input cannot exhaust the stack.
class JsonParser {
 public:
  explicit JsonParser(std::span<const std::uint8_t> text) : text_(text) {}

  // Returns the error text, or an empty string on success.
  std::string parse(Json& out) {
    skip_space();
    if (!value(out, 0)) return error_;
    skip_space();
    if (at_ < text_.size()) return unexpected();
    return {};
  }

 private:
  static constexpr int kMaxDepth = 512;

  bool fail(std::string message) {
    if (error_.empty()) error_ = std::move(message);
    return false;
  }
  std::string unexpected() {
    return at_ >= text_.size() ? "FormatException: Unexpected end of input (at offset " + std::to_string(at_) + ")"
                               : "FormatException: Unexpected character (at offset " + std::to_string(at_) + ")";
  }
  bool fail_here() { return fail(unexpected()); }

  void skip_space() {
    while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\t' || text_[at_] == '\n' || text_[at_] == '\r'))
      ++at_;
  }

  bool literal(const char* word, Json value, Json& out) {
    const std::size_t length = std::strlen(word);
    for (std::size_t i = 0; i < length; ++i) {
      if (at_ >= text_.size() || text_[at_] != static_cast<std::uint8_t>(word[i])) return fail_here();
      ++at_;
    }
    out = std::move(value);
    return true;
  }

  bool value(Json& out, int depth) {
    if (at_ >= text_.size()) return fail_here();
    if (depth > kMaxDepth) return fail("FormatException: Nesting too deep (at offset " + std::to_string(at_) + ")");
    switch (text_[at_]) {
      case '{':
        return object(out, depth);
      case '[':
        return array(out, depth);
      case '"': {
        std::string text;
        if (!string(text)) return false;
        out = std::move(text);
        return true;
      }
      case 't':
        return literal("true", true, out);
      case 'f':
        return literal("false", false, out);
      case 'n':
        return literal("null", nullptr, out);
      default:
        return number(out);
    }
  }

  bool object(Json& out, int depth) {
    ++at_;
    out = Json::object();
    skip_space();
    if (at_ < text_.size() && text_[at_] == '}') {
      ++at_;
      return true;
    }
    while (true) {
      skip_space();
      if (at_ >= text_.size() || text_[at_] != '"') return fail_here();
      std::string key;
      if (!string(key)) return false;
      skip_space();
      if (at_ >= text_.size() || text_[at_] != ':') return fail_here();
      ++at_;
      skip_space();
      Json item;
      if (!value(item, depth + 1)) return false;
      out[key] = std::move(item);
      skip_space();
      if (at_ >= text_.size()) return fail_here();
      if (text_[at_] == ',') {
        ++at_;
        continue;
      }
      if (text_[at_] == '}') {
        ++at_;
        return true;
      }
      return fail_here();
    }
  }

  bool array(Json& out, int depth) {
    ++at_;
    out = Json::array();
    skip_space();
    if (at_ < text_.size() && text_[at_] == ']') {
      ++at_;
      return true;
    }
    while (true) {
      skip_space();
      Json item;
      if (!value(item, depth + 1)) return false;
      out.push_back(std::move(item));
      skip_space();
      if (at_ >= text_.size()) return fail_here();
      if (text_[at_] == ',') {
        ++at_;
        continue;
      }
      if (text_[at_] == ']') {
        ++at_;
        return true;
      }
      return fail_here();
    }
  }

  static void append_utf8(std::string& out, std::uint32_t code) {
    if (code < 0x80) {
      out += static_cast<char>(code);
    } else if (code < 0x800) {
      out += static_cast<char>(0xC0 | (code >> 6));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else if (code < 0x10000) {
      out += static_cast<char>(0xE0 | (code >> 12));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (code >> 18));
      out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    }
  }

  bool hex4(std::uint32_t& code) {
    code = 0;
    for (int i = 0; i < 4; ++i) {
      if (at_ >= text_.size()) return fail_here();
      const std::uint8_t c = text_[at_];
      code <<= 4;
      if (c >= '0' && c <= '9')
        code |= c - '0';
      else if (c >= 'a' && c <= 'f')
        code |= c - 'a' + 10;
      else if (c >= 'A' && c <= 'F')
        code |= c - 'A' + 10;
      else
        return fail_here();
      ++at_;
    }
    return true;
  }

  bool string(std::string& out) {
    ++at_;  // the opening quote
    while (true) {
      if (at_ >= text_.size()) return fail_here();
      const std::uint8_t c = text_[at_];
      if (c == '"') {
        ++at_;
        return true;
      }
      if (c < 0x20) return fail_here();
      if (c != '\\') {
        out += static_cast<char>(c);
        ++at_;
        continue;
      }
      ++at_;
      if (at_ >= text_.size()) return fail_here();
      const std::uint8_t escape = text_[at_++];
      switch (escape) {
        case '"':
          out += '"';
          break;
        case '\\':
          out += '\\';
          break;
        case '/':
          out += '/';
          break;
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'n':
          out += '\n';
          break;
        case 'r':
          out += '\r';
          break;
        case 't':
          out += '\t';
          break;
        case 'u': {
          std::uint32_t code;
          if (!hex4(code)) return false;
          if (code >= 0xD800 && code < 0xDC00 && at_ + 1 < text_.size() && text_[at_] == '\\' &&
              text_[at_ + 1] == 'u') {
            const std::size_t save = at_;
            at_ += 2;
            std::uint32_t low;
            if (!hex4(low)) return false;
            if (low >= 0xDC00 && low < 0xE000)
              code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
            else
              at_ = save;
          }
          append_utf8(out, code);
          break;
        }
        default:
          --at_;
          return fail_here();
      }
    }
  }

  bool number(Json& out) {
    const std::size_t start = at_;
    auto digit = [&] { return at_ < text_.size() && text_[at_] >= '0' && text_[at_] <= '9'; };
    if (at_ < text_.size() && text_[at_] == '-') ++at_;
    if (!digit()) return fail_here();
    if (text_[at_] == '0') {
      ++at_;
    } else {
      while (digit()) ++at_;
    }
    bool integral = true;
    if (at_ < text_.size() && text_[at_] == '.') {
      integral = false;
      ++at_;
      if (!digit()) return fail_here();
      while (digit()) ++at_;
    }
    if (at_ < text_.size() && (text_[at_] == 'e' || text_[at_] == 'E')) {
      integral = false;
      ++at_;
      if (at_ < text_.size() && (text_[at_] == '+' || text_[at_] == '-')) ++at_;
      if (!digit()) return fail_here();
      while (digit()) ++at_;
    }
    const std::string token(reinterpret_cast<const char*>(text_.data() + start), at_ - start);
    if (integral) {
      errno = 0;
      char* end = nullptr;
      if (token[0] == '-') {
        const long long value = std::strtoll(token.c_str(), &end, 10);
        if (errno == 0) {
          out = static_cast<std::int64_t>(value);
          return true;
        }
      } else {
        const unsigned long long value = std::strtoull(token.c_str(), &end, 10);
        if (errno == 0) {
          if (value <= static_cast<unsigned long long>(std::numeric_limits<std::int64_t>::max()))
            out = static_cast<std::int64_t>(value);
          else
            out = static_cast<std::uint64_t>(value);
          return true;
        }
      }
    }
    out = std::strtod(token.c_str(), nullptr);  // overflow gives ±HUGE_VAL = ±Infinity, as in Dart
    return true;
  }

  std::span<const std::uint8_t> text_;
  std::size_t at_ = 0;
  std::string error_;
};

}  // namespace

bool parse_json(std::span<const std::uint8_t> text, Context& context) {
  // RFC 8259 8.1 forbids a byte order mark; the reference reports it and reads on.
  if (text.size() >= 3 && text[0] == 0xEF && text[1] == 0xBB && text[2] == 0xBF) {
    context.issues.at("INVALID_JSON", "", {arg_raw("BOM found at the beginning of UTF-8 stream.")});
    text = text.subspan(3);
  }
  // The reference decodes UTF-8 strictly before it parses (RFC 8259 8.1: JSON text is UTF-8).
  for (std::size_t i = 0; i < text.size();) {
    const std::uint8_t lead = text[i];
    std::size_t length = lead < 0x80           ? 1
                         : (lead >> 5) == 0x6  ? 2
                         : (lead >> 4) == 0xE  ? 3
                         : (lead >> 3) == 0x1E ? 4
                                               : 0;
    bool valid = length > 0 && i + length <= text.size();
    for (std::size_t k = 1; valid && k < length; ++k) valid = (text[i + k] & 0xC0) == 0x80;
    if (valid && length == 2) valid = lead >= 0xC2;  // overlong
    if (valid && length == 3) {
      const std::uint32_t code = ((lead & 0x0F) << 12) | ((text[i + 1] & 0x3F) << 6) | (text[i + 2] & 0x3F);
      valid = code >= 0x800 && (code < 0xD800 || code > 0xDFFF);  // overlong, surrogate
    }
    if (valid && length == 4) {
      const std::uint32_t code =
          ((lead & 0x07) << 18) | ((text[i + 1] & 0x3F) << 12) | ((text[i + 2] & 0x3F) << 6) | (text[i + 3] & 0x3F);
      valid = code >= 0x10000 && code <= 0x10FFFF;
    }
    if (!valid) {
      context.issues.at("INVALID_JSON", "",
                        {arg_raw("FormatException: Invalid UTF-8 byte (at offset " + std::to_string(i) + ")")});
      return false;
    }
    i += length;
  }
  const std::string error = JsonParser(text).parse(context.root);
  if (!error.empty()) {
    context.issues.at("INVALID_JSON", "", {arg_raw(error)});
    return false;
  }
  if (!context.root.is_object()) {
    context.issues.at("TYPE_MISMATCH", "", {arg_json(context.root), arg("object")});
    return false;
  }
  return true;
}

}  // namespace gltf_pbr::structure
