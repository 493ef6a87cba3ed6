// Text from a file, made safe to show to people on a terminal.
#pragma once
#include <string>
#include <string_view>

namespace gltf_pbr {

// Escapes what a terminal would act on instead of showing: C0 controls (ESC, CR, newline...), DEL,
// C1 controls (U+0080-U+009F, e.g. CSI), bidirectional overrides, bytes that are not UTF-8 and the
// backslash itself, as \xNN, so a material name cannot move the cursor, retitle the window, forge
// a line or pass for an escape. Other valid UTF-8 text passes unchanged.
// JSON and SARIF outputs keep the exact strings; only text for people goes through this.
std::string printable(std::string_view text);

// The text itself when it is valid UTF-8 (the common case: no copy); otherwise each byte that
// starts no valid sequence replaced by U+FFFD, as JSON output requires (RFC 8259 section 8.1).
std::string valid_utf8(std::string text);

// A path as a URL path (RFC 3986 section 2): unreserved bytes and '/' as they are, every other byte
// %XX, so a file named in any bytes (not UTF-8, or with '#', '?', '%', spaces) is still addressed
// by it: the gallery's links, SARIF's artifact locations.
std::string url_path(std::string_view path);

}  // namespace gltf_pbr
