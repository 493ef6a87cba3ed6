// JSON pointers (RFC 6901) into the glTF document, as every issue and error names its place.
#pragma once
#include <string>
#include <string_view>

namespace gltf_pbr {

// One reference token, escaped (RFC 6901 section 3): "~" becomes "~0", then "/" becomes "~1", so
// names such as an attribute "_A/B" or an extension key stay one token.
std::string escape_pointer_token(std::string_view token);

// The pointer to element `index` of a top-level array: pointer("images", 3) is "/images/3".
std::string pointer(std::string_view collection, int index);

}  // namespace gltf_pbr
