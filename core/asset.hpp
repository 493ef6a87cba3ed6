// The one in-memory asset that every step (convert, validate, preview) shares.
// Images stay encoded and Draco meshes compressed until a step asks for them (DESIGN.md, "Pay
// only for what the scene uses").
#pragma once
#include <tiny_gltf.h>

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/files.hpp"
#include "core/json_pointer.hpp"  // pointer(), which every user of an Asset needs
#include "core/resources.hpp"

namespace gltf_pbr {

struct LoadOptions {
  bool allow_outside_uris = false;  // read absolute or "../" URIs (refused by default)
  // The file's resources when another step of the same run already read some (the structure
  // step of validate, or of convert's value scan); its policy then governs, not
  // allow_outside_uris. A new one when null.
  std::shared_ptr<FileResources> resources;
  // The file's bytes when the caller has already read or mapped them (validate, convert): the file
  // is not read again. They must stay valid for the call.
  std::optional<std::span<const std::uint8_t>> file_bytes;
};

// The decoded bytes of EXT_meshopt_compression bufferViews (core/meshopt.hpp), by view index,
// decoded when a step first reads one: convert, which reads no geometry, decodes nothing. Failures
// are kept too, so a bad view is decoded once. Their sum is bounded (meshopt_decode_budget). A copy
// starts empty, since prune and save renumber views; prune empties it, so spans taken from it
// before a prune must not be used after.
class DecodedViews {
 public:
  struct Entry {
    std::optional<std::vector<std::uint8_t>> bytes;
    std::string problem;  // why there are none
  };
  DecodedViews() = default;
  DecodedViews(const DecodedViews&) {}
  DecodedViews& operator=(const DecodedViews&);
  // View `index`'s entry, from `decode` the first time unless its `decoded_size` bytes would take
  // the total past `budget`. Decoding runs under the lock: meshoptimizer decodes about 1 GB/s.
  const Entry& find_or_decode(int index, std::uint64_t decoded_size, std::uint64_t budget,
                              const std::function<std::optional<std::vector<std::uint8_t>>(std::string&)>& decode) const;

 private:
  mutable std::mutex mutex_;
  mutable std::map<int, Entry> views_;  // map: entries stay where they are
  mutable std::uint64_t decoded_bytes_ = 0;
};

struct Asset {
  fs::path path;                      // the file it was loaded from
  bool binary = false;                // GLB container
  tinygltf::Model model;              // data-URI and new images keep their encoded bytes in Image::image
  std::vector<std::string> warnings;  // problems that did not stop loading
  std::string original_json;          // the JSON text as read, for the byte-for-byte copy path
  // Image files named by a URI, mapped, not read: a page is read when a step first touches it, so
  // an image that is only passed through or replaced costs no copy (issue 11). Keyed by the URI
  // as written; copies of the asset share the mappings.
  std::map<std::string, std::shared_ptr<const MappedFile>> image_files;
  DecodedViews decoded_views;
  // What it was loaded through (external files, decoded Draco meshes); null for an asset built in
  // memory, whose Draco meshes are then decoded on every request.
  std::shared_ptr<FileResources> resources;
};

// Document garbage collection: removes textures, images and samplers that nothing references
// any more, and the bufferViews that only removed images used (compacting their buffers, and
// removing a buffer left with none of its bytes: glTF requires byteLength >= 1).
// Extensions whose references it cannot follow make it keep everything (reported in warnings).
struct PruneResult {
  int textures = 0, images = 0, samplers = 0, buffer_views = 0, buffers = 0;
};
PruneResult prune_unused(Asset& asset);

// Rewrites every integer under `key` anywhere inside `value` through `remap` (old -> new index).
void remap_in_value(tinygltf::Value& value, const std::string& key, const std::vector<int>& remap);

// Throws InputError (file, JSON pointer, reason) for bad input.
Asset load_asset(const fs::path& path, const LoadOptions& options = {});

// The URIs of the external files a glTF or GLB file's buffers and images name (data URIs left
// out), in document order, as written: what a result computed from the file also depends on.
// Reads only the JSON; std::nullopt when the container or the JSON cannot be read that far.
std::optional<std::vector<std::string>> external_uris(std::span<const std::uint8_t> file_bytes);

// Writes the asset as .glb or .gltf (by extension of `output`), all files atomically.
// Buffers and images keep their bytes; a .gltf's external resources are written beside it.
// Input files are never overwritten, except the asset's own file when replace_input is set
// (--in-place); its resources still are not. Throws InputError or std::runtime_error; leaves
// nothing behind on failure. Returns the files written, the main file last.
std::vector<fs::path> save_asset(Asset& asset, const fs::path& output, bool replace_input = false);

// Copies the input file and every external resource it references to `output` unchanged
// (same format only). Used when a step changed nothing. `file_bytes`: the input file's bytes when
// the caller holds them (convert), so the file is not read again. Returns the files written, the
// main file last.
std::vector<fs::path> copy_asset_verbatim(const Asset& asset, const fs::path& output,
                                          std::optional<std::span<const std::uint8_t>> file_bytes = std::nullopt);

// A GLB container (glTF 2.0 section 4.4) holding the JSON text and the BIN chunk.
Bytes glb_bytes(const std::string& json_text, std::span<const std::uint8_t> bin);

// The bytes of bufferView `index`: a range of its buffer or, for a view compressed with
// EXT_meshopt_compression, its decoded bytes. Nothing, with `problem` set, when the view, its
// buffer or its compressed source does not exist, does not fit, or does not decode.
std::optional<std::span<const std::uint8_t>> buffer_view_bytes(const Asset& asset, int index, std::string& problem);

// The encoded bytes of image `index`: Image::image when it holds them (a data URI, or an image a
// step made), else its bufferView, else its mapped file. Empty when there are none.
std::span<const std::uint8_t> encoded_image_bytes(const Asset& asset, int index);

// Gives back the pages of image `index`'s mapped file once a step has decoded it: the texels are
// what it keeps (a 4096² PNG holds ~13 MB). Nothing happens for images held in memory.
void release_encoded_image_pages(const Asset& asset, int index);

// Counters that prove lazy work: how often assets were loaded and pixels or meshes decoded.
struct WorkCounters {
  std::atomic<long> assets_loaded{0};  // load_asset calls: what a run served from a cache did not do
  std::atomic<long> json_texts_read{0};  // read_json calls (core/json.hpp)
  std::atomic<long> images_decoded{0};
  std::atomic<long> png_streams_inflated{0};  // PNG image data inflated by libdeflate, not libspng (core/png.cpp)
  std::atomic<long> meshes_decoded{0};
  std::atomic<long> views_decoded{0};  // EXT_meshopt_compression bufferViews
  std::atomic<long> files_opened{0};   // external buffer and image files (FileResources)
  std::atomic<long> documents_read{0};  // a .gltf or .glb file's own bytes, read or mapped
};
WorkCounters& work_counters();

}  // namespace gltf_pbr
