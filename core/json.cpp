#include "core/json.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <unordered_map>

#include "core/asset.hpp"
#include "core/json_pointer.hpp"

namespace gltf_pbr {

namespace {

// The first byte at which `text` is not UTF-8: overlong forms, surrogates and code points above
// U+10FFFF are refused (RFC 3629 section 3), as Dart's strict decoder does.
std::optional<std::size_t> first_invalid_utf8(std::span<const std::uint8_t> text) {
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
    if (!valid) return i;
    i += length;
  }
  return std::nullopt;
}

class JsonParser {
 public:
  JsonParser(std::span<const std::uint8_t> text, JsonFlawsSeen* seen) : text_(text), seen_(seen) {}

  std::optional<JsonProblem> parse(JsonDocument& out) {
    skip_space();
    if (!value(out, 0)) return problem_;
    skip_space();
    if (at_ < text_.size()) return unexpected();
    return std::nullopt;
  }

 private:
  static constexpr std::size_t kLinearKeys = 16;

  bool fail(JsonProblem problem) {
    if (!problem_) problem_ = problem;
    return false;
  }
  JsonProblem unexpected() const {
    return {at_ >= text_.size() ? JsonProblem::Kind::UnexpectedEnd : JsonProblem::Kind::UnexpectedCharacter, at_};
  }
  bool fail_here() { return fail(unexpected()); }

  void skip_space() {
    while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\t' || text_[at_] == '\n' || text_[at_] == '\r'))
      ++at_;
  }

  bool literal(const char* word, JsonDocument value, JsonDocument& out) {
    const std::size_t length = std::strlen(word);
    for (std::size_t i = 0; i < length; ++i) {
      if (at_ >= text_.size() || text_[at_] != static_cast<std::uint8_t>(word[i])) return fail_here();
      ++at_;
    }
    out = std::move(value);
    return true;
  }

  bool value(JsonDocument& out, int depth) {
    if (at_ >= text_.size()) return fail_here();
    if (depth > kMaxJsonDepth) return fail({JsonProblem::Kind::TooDeep, at_});
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

  bool object(JsonDocument& out, int depth) {
    ++at_;
    out = JsonDocument::object();
    // ordered_map is a vector of members; it hides the vector's indexing, which this reads by.
    auto& members = static_cast<JsonDocument::object_t::Container&>(out.get_ref<JsonDocument::object_t&>());
    std::unordered_map<std::string, std::size_t> positions;  // key -> member, once past kLinearKeys
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
      JsonDocument item;
      if (!value(item, depth + 1)) return false;
      // A repeated key keeps its first position and takes the last value. ordered_json finds a key
      // by a linear search, so an object of a million keys would take 10^12 steps: past a few keys
      // an index finds them instead.
      const auto found = [&]() -> std::size_t {
        if (members.size() <= kLinearKeys) {
          for (std::size_t i = 0; i < members.size(); ++i)
            if (members[i].first == key) return i;
          return members.size();
        }
        if (positions.empty())
          for (std::size_t i = 0; i < members.size(); ++i) positions.emplace(members[i].first, i);
        const auto position = positions.find(key);
        return position == positions.end() ? members.size() : position->second;
      }();
      if (found < members.size()) {
        members[found].second = std::move(item);
      } else {
        if (!positions.empty()) positions.emplace(key, members.size());
        members.emplace_back(std::move(key), std::move(item));
      }
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

  bool array(JsonDocument& out, int depth) {
    ++at_;
    out = JsonDocument::array();
    skip_space();
    if (at_ < text_.size() && text_[at_] == ']') {
      ++at_;
      return true;
    }
    while (true) {
      skip_space();
      JsonDocument item;
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
          if (seen_ && code >= 0xD800 && code < 0xE000) seen_->lone_surrogate = true;
          append_utf8(out, code);
          break;
        }
        default:
          --at_;
          return fail_here();
      }
    }
  }

  bool number(JsonDocument& out) {
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
    const double number = std::strtod(token.c_str(), nullptr);  // overflow gives ±HUGE_VAL = ±Infinity, as in Dart
    if (seen_ && seen_->first_non_finite.empty() && !std::isfinite(number)) seen_->first_non_finite = token;
    out = number;
    return true;
  }

  std::span<const std::uint8_t> text_;
  JsonFlawsSeen* seen_;
  std::size_t at_ = 0;
  std::optional<JsonProblem> problem_;
};

std::optional<JsonFlaw::Kind> flaw_of_text(const std::string& text) {
  const std::span<const std::uint8_t> bytes(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  return first_invalid_utf8(bytes) ? std::optional(JsonFlaw::Kind::NotUnicode) : std::nullopt;
}

// Depth-first in document order; `at` receives the pointer, built on the way back up.
std::optional<JsonFlaw::Kind> find_flaw(const JsonDocument& value, std::string& at) {
  if (value.is_number_float() && !std::isfinite(value.get<double>())) return JsonFlaw::Kind::NonFiniteNumber;
  if (value.is_string()) return flaw_of_text(value.get_ref<const std::string&>());
  if (value.is_array()) {
    for (std::size_t i = 0; i < value.size(); ++i)
      if (const auto flaw = find_flaw(value[i], at)) return (at.insert(0, "/" + std::to_string(i)), flaw);
  } else if (value.is_object()) {
    for (const auto& [key, item] : value.items()) {
      std::optional<JsonFlaw::Kind> flaw = flaw_of_text(key);
      if (!flaw) flaw = find_flaw(item, at);
      if (flaw) return (at.insert(0, "/" + escape_pointer_token(key)), flaw);
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<JsonProblem> read_json(std::span<const std::uint8_t> text, JsonDocument& out, JsonFlawsSeen* seen) {
  ++work_counters().json_texts_read;
  if (const auto at = first_invalid_utf8(text)) return JsonProblem{JsonProblem::Kind::InvalidUtf8, *at};
  return JsonParser(text, seen).parse(out);
}

std::optional<JsonFlaw> first_flaw(const JsonDocument& value) {
  std::string at;
  if (const std::optional<JsonFlaw::Kind> kind = find_flaw(value, at)) return JsonFlaw{*kind, at};
  return std::nullopt;
}

std::optional<std::int64_t> integer_value(const JsonDocument& value) {
  constexpr auto most = std::numeric_limits<std::int64_t>::max();
  if (value.is_number_unsigned())
    return static_cast<std::int64_t>(std::min<std::uint64_t>(value.get<std::uint64_t>(), most));
  if (value.is_number_integer()) return value.get<std::int64_t>();
  if (!value.is_number_float()) return std::nullopt;
  const double number = value.get<double>();
  if (!std::isfinite(number) || std::trunc(number) != number) return std::nullopt;
  // 2^63 is the first double above the range; the lowest int64 is exactly -2^63.
  if (number >= 9223372036854775808.0) return most;
  return static_cast<std::int64_t>(std::max(number, -9223372036854775808.0));
}

}  // namespace gltf_pbr
