// The GLB container (glTF 2.0 section 4.4 "Binary glTF Layout"): its constants and the one walk over
// its chunks, for the structure step (which reports every fault in the reference's codes) and the
// loader (which refuses the first). Reads no byte past the span, whatever the lengths claim.
#pragma once
#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>

#include "core/byte_order.hpp"

namespace gltf_pbr {

inline constexpr std::uint32_t kGlbMagic = 0x46546C67;      // "glTF"
inline constexpr std::uint32_t kGlbChunkJson = 0x4E4F534A;  // "JSON"
inline constexpr std::uint32_t kGlbChunkBin = 0x004E4942;   // "BIN\0"
inline constexpr std::uint64_t kGlbHeaderSize = 12, kGlbChunkHeaderSize = 8;

// One chunk as it stands in the bytes: `data` is its `length` bytes, or fewer when the bytes end
// inside it (then !whole()).
struct GlbChunk {
  std::uint64_t offset = 0;  // of its 8-byte header
  std::uint32_t length = 0, type = 0;
  std::span<const std::uint8_t> data;
  bool whole() const { return data.size() == length; }
  std::uint64_t end() const { return offset + kGlbChunkHeaderSize + length; }  // as declared
};

// Chunks from byte 12 on, in order, until one ends exactly at `declared_end` (the header's length)
// or the bytes end. A chunk whose declared length runs past `declared_end` is still read as far as
// the bytes go; what that means is the caller's to judge.
class GlbChunks {
 public:
  GlbChunks(std::span<const std::uint8_t> bytes, std::uint64_t declared_end)
      : bytes_(bytes), declared_end_(declared_end) {}

  // Whether the walk is over: at `declared_end`, at the end of the bytes, or cut inside a chunk.
  bool done() const { return cut_ || position_ == declared_end_ || position_ >= bytes_.size(); }
  // The next chunk; std::nullopt when done(), or when the bytes end inside its header.
  std::optional<GlbChunk> next() {
    if (done()) return std::nullopt;
    if (bytes_.size() - position_ < kGlbChunkHeaderSize) {
      cut_ = true;
      return std::nullopt;
    }
    GlbChunk chunk;
    chunk.offset = position_;
    chunk.length = little_endian32(bytes_, position_);
    chunk.type = little_endian32(bytes_, position_ + 4);
    const std::uint64_t start = position_ + kGlbChunkHeaderSize;
    chunk.data = bytes_.subspan(start, std::min<std::uint64_t>(chunk.length, bytes_.size() - start));
    cut_ = !chunk.whole();
    position_ = start + chunk.data.size();
    return chunk;
  }
  // Where the walk stopped: the end of the last whole chunk, or the end of the bytes.
  std::uint64_t position() const { return position_; }

 private:
  std::span<const std::uint8_t> bytes_;
  std::uint64_t declared_end_;
  std::uint64_t position_ = kGlbHeaderSize;
  bool cut_ = false;
};

}  // namespace gltf_pbr
