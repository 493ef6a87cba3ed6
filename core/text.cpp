#include "core/text.hpp"

#include <cctype>
#include <cstdint>

namespace gltf_pbr {
namespace {

void escape(std::string& out, unsigned char byte) {
  static constexpr char kHex[] = "0123456789abcdef";
  out += "\\x";
  out += kHex[byte >> 4];
  out += kHex[byte & 15];
}

// Length of the valid UTF-8 sequence at `i` (RFC 3629 section 4: no overlongs, no surrogates), 0 if none.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char lead = b(i);
  std::size_t n = lead >= 0xF0 && lead <= 0xF4 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC2 && lead <= 0xDF ? 2 : 0;
  if (n == 0 || (lead >= 0xF5) || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((b(i + k) & 0xC0) != 0x80) return 0;
  if (lead == 0xE0 && b(i + 1) < 0xA0) return 0;   // overlong
  if (lead == 0xED && b(i + 1) >= 0xA0) return 0;  // surrogate
  if (lead == 0xF0 && b(i + 1) < 0x90) return 0;   // overlong
  if (lead == 0xF4 && b(i + 1) >= 0x90) return 0;  // above U+10FFFF
  return n;
}

}  // namespace

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x80) {
      if (byte < 0x20 || byte == 0x7F || byte == '\\')  // a backslash too, so "\x1b" cannot be forged
        escape(out, byte);
      else
        out += static_cast<char>(byte);
      ++i;
      continue;
    }
    const std::size_t n = utf8_length(text, i);
    const bool c1_control = n == 2 && byte == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0;
    // Bidirectional embeddings, overrides and isolates (U+202A-202E, U+2066-2069) reorder what
    // follows them on screen, so a name could show as something it is not.
    const auto b1 = n == 3 ? static_cast<unsigned char>(text[i + 1]) : 0,
               b2 = n == 3 ? static_cast<unsigned char>(text[i + 2]) : 0;
    const bool bidi =
        byte == 0xE2 && ((b1 == 0x80 && b2 >= 0xAA && b2 <= 0xAE) || (b1 == 0x81 && b2 >= 0xA6 && b2 <= 0xA9));
    if (n == 0 || c1_control || bidi) {
      for (std::size_t k = 0; k < (n ? n : 1); ++k) escape(out, static_cast<unsigned char>(text[i + k]));
      i += n ? n : 1;
      continue;
    }
    out.append(text.substr(i, n));
    i += n;
  }
  return out;
}

std::string valid_utf8(std::string text) {
  std::size_t i = 0;
  while (i < text.size() && (static_cast<unsigned char>(text[i]) < 0x80 || utf8_length(text, i) > 0))
    i += static_cast<unsigned char>(text[i]) < 0x80 ? 1 : utf8_length(text, i);
  if (i == text.size()) return text;
  std::string out = text.substr(0, i);
  while (i < text.size()) {
    const std::size_t n = static_cast<unsigned char>(text[i]) < 0x80 ? 1 : utf8_length(text, i);
    if (n == 0) {
      out += "\xEF\xBF\xBD";  // U+FFFD REPLACEMENT CHARACTER
      ++i;
    } else {
      out.append(text, i, n);
      i += n;
    }
  }
  return out;
}

std::string url_path(std::string_view path) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (const char c : path) {
    const auto byte = static_cast<unsigned char>(c);
    if (std::isalnum(byte) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      out += c;
    } else {
      out += '%';
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    }
  }
  return out;
}

}  // namespace gltf_pbr
