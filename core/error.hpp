// User-facing errors and internal invariants (pbrt's split: ErrorExit vs CHECK).
#pragma once
#include <sstream>
#include <string>

#include "gltf_pbr/error.hpp"  // InputError, OutputError: public, thrown through the library

namespace gltf_pbr {

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
