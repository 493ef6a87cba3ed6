// The errors gltf-pbr reports to its callers, in the library as in the tool.
#pragma once
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "gltf_pbr/export.hpp"

namespace gltf_pbr {

// A place in a file named by its byte, where no JSON pointer reaches (a GLB header, cut JSON).
struct ByteOffset {
  std::uint64_t value;
};

// Bad input: names the file, a JSON pointer (RFC 6901) or a byte offset, and the reason.
struct GLTF_PBR_API InputError : std::runtime_error {
  InputError(std::string file_, std::string pointer_, std::string reason_)
      : std::runtime_error(file_ + (pointer_.empty() ? "" : ": " + pointer_) + ": " + reason_),
        file(std::move(file_)),
        pointer(std::move(pointer_)),
        reason(std::move(reason_)) {}
  InputError(std::string file_, ByteOffset at, std::string reason_)
      : std::runtime_error(file_ + ": " + where(std::string(), at.value) + ": " + reason_),
        file(std::move(file_)),
        reason(std::move(reason_)),
        offset(at.value) {}
  // Where in the file, as messages say it: the JSON pointer, or "byte N"; empty when neither is known.
  static std::string where(const std::string& pointer, std::optional<std::uint64_t> offset) {
    return offset ? "byte " + std::to_string(*offset) : pointer;
  }
  std::string file, pointer, reason;
  std::optional<std::uint64_t> offset;  // set instead of pointer by the ByteOffset constructor
};

// An output that cannot be written (a full disk, a missing folder, permissions), with errno's text.
struct GLTF_PBR_API OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace gltf_pbr
