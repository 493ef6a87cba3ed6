#include "core/json_pointer.hpp"

namespace gltf_pbr {

std::string escape_pointer_token(std::string_view token) {
  std::string escaped;
  escaped.reserve(token.size());
  for (char c : token) {
    if (c == '~')
      escaped += "~0";
    else if (c == '/')
      escaped += "~1";
    else
      escaped += c;
  }
  return escaped;
}

std::string pointer(std::string_view collection, int index) {
  return "/" + std::string(collection) + "/" + std::to_string(index);
}

}  // namespace gltf_pbr
