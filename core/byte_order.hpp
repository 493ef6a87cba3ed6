// Reading fixed-size integers out of file bytes in the byte order each format names: little-endian
// for GLB (glTF 2.0 section 4.4), KTX2 and WebP; big-endian (network order) for PNG and JPEG. The
// caller has checked that the bytes are there.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

namespace gltf_pbr {

inline std::uint32_t little_endian32(std::span<const std::uint8_t> b, std::size_t at) {
  return std::uint32_t(b[at]) | (std::uint32_t(b[at + 1]) << 8) | (std::uint32_t(b[at + 2]) << 16) |
         (std::uint32_t(b[at + 3]) << 24);
}
inline std::uint64_t little_endian64(std::span<const std::uint8_t> b, std::size_t at) {
  return std::uint64_t(little_endian32(b, at)) | (std::uint64_t(little_endian32(b, at + 4)) << 32);
}
inline std::uint32_t little_endian24(std::span<const std::uint8_t> b, std::size_t at) {
  return std::uint32_t(b[at]) | (std::uint32_t(b[at + 1]) << 8) | (std::uint32_t(b[at + 2]) << 16);
}
inline std::uint32_t big_endian32(std::span<const std::uint8_t> b, std::size_t at) {
  return (std::uint32_t(b[at]) << 24) | (std::uint32_t(b[at + 1]) << 16) | (std::uint32_t(b[at + 2]) << 8) | b[at + 3];
}
inline std::uint32_t big_endian16(std::span<const std::uint8_t> b, std::size_t at) {
  return (std::uint32_t(b[at]) << 8) | b[at + 1];
}

}  // namespace gltf_pbr
