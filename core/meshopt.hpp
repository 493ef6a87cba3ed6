// EXT_meshopt_compression (Khronos glTF repository, extensions/2.0/Vendor/EXT_meshopt_compression):
// a bufferView whose bytes are stored compressed in another buffer range, decoded with Debian's
// libmeshoptimizer. The one decoder every step reads compressed views through: core's accessor
// reader (preview, mesh checks) and the structure step's data checks. Convert never decodes: the
// compressed bytes are written back as they were.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/json.hpp"

namespace tinygltf {
struct Buffer;
struct BufferView;
}  // namespace tinygltf

namespace gltf_pbr {

enum class MeshoptMode { Attributes, Triangles, Indices };
enum class MeshoptFilter { None, Octahedral, Quaternion, Exponential };

std::optional<MeshoptMode> meshopt_mode(std::string_view name);      // "ATTRIBUTES", "TRIANGLES", "INDICES"
std::optional<MeshoptFilter> meshopt_filter(std::string_view name);  // "NONE", "OCTAHEDRAL", ...

// The extension object of one bufferView: where the compressed bytes are and how they decode.
struct MeshoptView {
  std::int64_t buffer = -1;         // the buffer holding the compressed bytes
  std::uint64_t byte_offset = 0;    // into that buffer
  std::uint64_t byte_length = 0;    // of the compressed bytes
  std::uint64_t byte_stride = 0;    // of one decoded element
  std::uint64_t count = 0;          // decoded elements
  MeshoptMode mode = MeshoptMode::Attributes;
  MeshoptFilter filter = MeshoptFilter::None;
};

// The first rule of the extension's "For the extension object to be valid" list that `view`
// breaks, given its parent bufferView's byteLength and byteStride (0 when it has none); empty when
// it breaks none. The decoder asserts on these, so nothing is decoded before they hold.
std::string meshopt_layout_problem(const MeshoptView& view, std::uint64_t parent_byte_length,
                                   std::uint64_t parent_byte_stride);

// Decodes the compressed bytes of `view` into byte_stride × count bytes, the filter applied.
// Returns nothing with `problem` set when the layout is invalid, when the bytes are fewer than the
// bitstream needs for that many elements (checked before anything is allocated, so a hostile count
// costs nothing), or when meshoptimizer refuses them.
std::optional<std::vector<std::uint8_t>> decode_meshopt(std::span<const std::uint8_t> compressed,
                                                        const MeshoptView& view, std::string& problem);

// How many decoded bytes a file's compressed views may add up to, given the bytes its buffers
// store: 64 times as many (no bitstream expands more, see decode_meshopt) plus 1 MiB. Views may
// share one compressed range, so each view's own bound does not bound their sum.
std::uint64_t meshopt_decode_budget(std::uint64_t stored_bytes);
// Why decoding `size` more bytes after `decoded` would break `budget`; empty when it would not.
std::string meshopt_budget_problem(std::uint64_t decoded, std::uint64_t size, std::uint64_t budget);

// The extension object of a tinygltf bufferView, or nothing when it has none. `problem` is set
// when the object is there but malformed (a member missing or of the wrong type). One reader for
// both documents: the same for the object itself in our JSON tree (the structure step's).
std::optional<MeshoptView> meshopt_view(const tinygltf::BufferView& view, std::string& problem);
std::optional<MeshoptView> meshopt_view_from_json(const JsonDocument& extension, std::string& problem);

// Whether a buffer is marked {"fallback": true}: a placeholder with no bytes of its own that only
// compressed bufferViews reference ("Fallback buffers"). The tinygltf buffer, or the buffer object
// in our JSON tree (the loader's pre-pass, before tinygltf reads the file).
bool is_meshopt_fallback(const tinygltf::Buffer& buffer);
bool is_meshopt_fallback_json(const JsonDocument& buffer);

// A fallback buffer without bytes (no uri, nothing loaded): saving writes no file for it and derives
// its byteLength from the views it holds.
bool is_meshopt_placeholder(const tinygltf::Buffer& buffer);

// Moves the compressed source of a bufferView (one with the extension) to `buffer` at `byte_offset`:
// what saving and pruning do when they merge or compact the buffers the compressed bytes live in.
void set_meshopt_source(tinygltf::BufferView& view, int buffer, std::uint64_t byte_offset);

// The buffer a bufferView's extension object names, read as meshopt_view reads it, also when the
// rest of the object is malformed; and the same member set alone (pruning renumbers buffers).
std::optional<std::uint64_t> meshopt_source_buffer(const tinygltf::BufferView& view);
void set_meshopt_source_buffer(tinygltf::BufferView& view, int buffer);

}  // namespace gltf_pbr
