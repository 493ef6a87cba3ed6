// core/json_pointer: RFC 6901 token escaping, shared by every step that names a place in a file.
#include "core/json_pointer.hpp"

#include <gtest/gtest.h>

namespace gltf_pbr {
namespace {

// RFC 6901 section 4 evaluates "~1" to "/" and then "~0" to "~": the reverse of the escape.
std::string unescape(std::string_view token) {
  std::string out;
  for (std::size_t i = 0; i < token.size(); ++i) {
    if (token[i] == '~' && i + 1 < token.size()) {
      out += token[i + 1] == '1' ? '/' : '~';
      ++i;
    } else {
      out += token[i];
    }
  }
  return out;
}

TEST(JsonPointer, EscapedTokensHoldNoSlashAndUnescapeToTheOriginal) {
  for (std::string_view token : {"", "POSITION", "a/b", "~", "~1", "/~0/", "KHR_materials_pbrSpecularGlossiness",
                                 "_CUSTOM~/ATTRIBUTE", "~~//"}) {
    const std::string escaped = escape_pointer_token(token);
    EXPECT_EQ(escaped.find('/'), std::string::npos) << token;
    EXPECT_EQ(unescape(escaped), token);
  }
  EXPECT_EQ(escape_pointer_token("a/b~c"), "a~1b~0c");
  EXPECT_EQ(escape_pointer_token("~1"), "~01");  // not "/": "~" is escaped first (RFC 6901 section 4)
}

TEST(JsonPointer, CollectionElement) { EXPECT_EQ(pointer("accessors", 12), "/accessors/12"); }

}  // namespace
}  // namespace gltf_pbr
