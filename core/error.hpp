// User-facing errors and internal invariants (pbrt's split: ErrorExit vs CHECK).
#pragma once
#include <cstdint>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

namespace gltf_pbr {

// A place in a file named by its byte, where no JSON pointer reaches (a GLB header, cut JSON).
struct ByteOffset {
  std::uint64_t value;
};

// Bad input: names the file, a JSON pointer (RFC 6901) or a byte offset, and the reason.
struct InputError : std::runtime_error {
  InputError(std::string file_, std::string pointer_, std::string reason_)
      : std::runtime_error(file_ + (pointer_.empty() ? "" : ": " + pointer_) + ": " + reason_),
        file(std::move(file_)),
        pointer(std::move(pointer_)),
        reason(std::move(reason_)) {}
  InputError(std::string file_, ByteOffset at, std::string reason_)
      : std::runtime_error(file_ + ": byte " + std::to_string(at.value) + ": " + reason_),
        file(std::move(file_)),
        reason(std::move(reason_)),
        offset(at.value) {}
  std::string file, pointer, reason;
  std::optional<std::uint64_t> offset;  // set instead of pointer by the ByteOffset constructor
};

// An output that cannot be written (a full disk, a missing folder, permissions), with errno's text.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void check_failed(const char* expr, const std::string& operands, const char* where);

}  // namespace gltf_pbr

// Internal invariant: prints both operands when it fails.
#define GLTF_PBR_CHECK_OP(a, op, b)                                           \
  do {                                                                        \
    const auto& check_a_ = (a);                                               \
    const auto& check_b_ = (b);                                               \
    if (!(check_a_ op check_b_)) {                                            \
      std::ostringstream check_os_;                                           \
      check_os_ << #a " = " << check_a_ << ", " #b " = " << check_b_;         \
      ::gltf_pbr::check_failed(#a " " #op " " #b, check_os_.str(), __FILE__); \
    }                                                                         \
  } while (0)
#define CHECK_EQ(a, b) GLTF_PBR_CHECK_OP(a, ==, b)
#define CHECK_LE(a, b) GLTF_PBR_CHECK_OP(a, <=, b)
#define CHECK_LT(a, b) GLTF_PBR_CHECK_OP(a, <, b)
