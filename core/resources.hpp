// The resources of one glTF file, as every step reads them: the external files its URIs name,
// resolved through the one path policy (core/files.hpp resolve_uri) and mapped once however many
// steps read them, its Draco meshes, decoded once, and its JSON tree, read once. `validate` (and
// `convert`, for its value scan) hands one to the structure step and to the loader, so the JSON is
// parsed once, an image file or a .bin is opened once and a Draco mesh decoded once per file; an
// Asset keeps the one it was loaded with, for the steps that run on it.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/files.hpp"
#include "core/json.hpp"

namespace draco {
class Mesh;
}

namespace gltf_pbr {

class FileResources {
 public:
  // `folder` is the asset's folder, against which URIs resolve; `allow_outside` is the policy's
  // one switch (--allow-outside-uris). `keep_draco_meshes`: hold decoded meshes for the file's
  // later steps (validate's structure and mesh steps both read them) at the cost of their memory;
  // without it each request decodes and nothing is held.
  FileResources(fs::path folder, bool allow_outside, bool keep_draco_meshes = false);
  FileResources(const FileResources&) = delete;
  FileResources& operator=(const FileResources&) = delete;

  const fs::path& folder() const { return folder_; }
  bool allow_outside() const { return allow_outside_; }

  struct External {
    ResolvedUri resolved;                    // Readable, or why not (NotFound, Refused)
    std::shared_ptr<const MappedFile> file;  // set when Readable and the file could be mapped
  };
  // The file that `uri` (as written, not a data URI) names, mapped on first use and kept: later
  // calls, from any step or thread, get the same mapping (one per spelling: "a.bin" and "./a.bin"
  // map twice). Pages are read as they are touched; as with any mapping, a file truncated while
  // mapped ends the process with SIGBUS when the lost pages are read.
  const External& external(const std::string& uri);
  // Every file external() has resolved as readable so far: what the asset was read from, which a
  // save must never overwrite, whether or not the converted asset still names it.
  std::vector<fs::path> files_read() const;

  struct DracoMesh {
    std::shared_ptr<const draco::Mesh> mesh;  // null when the data does not decode
    std::string problem;                      // libdraco's reason then
  };
  // The mesh that KHR_draco_mesh_compression data decodes to; with keep_draco_meshes decoded once
  // per distinct data (keyed by the bytes' XXH3-128, so the structure step's copy of a buffer and
  // the loader's find the same entry). Counts into work_counters().meshes_decoded.
  DracoMesh draco_mesh(std::span<const std::uint8_t> compressed);

  // The file's JSON tree (core/json.hpp) with what its reader saw, handed from the step that read
  // it to the next one that needs it: the structure step keeps it, the loader takes it. It is kept
  // with the XXH3 hash of the text it was read from (the GLB's JSON chunk or the whole file), and
  // taken only for the same text, so a file that changed between the two reads is read again.
  // Taking forgets it, so its memory goes with the one step that uses it.
  struct Document {
    JsonDocument root;
    JsonFlawsSeen flaws;
  };
  void keep_document(Document document, std::span<const std::uint8_t> text);
  std::optional<Document> take_document(std::span<const std::uint8_t> text);

 private:
  fs::path folder_;
  bool allow_outside_;
  bool keep_draco_meshes_;
  mutable std::mutex mutex_;
  std::map<std::string, External> externals_;  // map: entries stay where they are
  std::map<std::pair<std::uint64_t, std::uint64_t>, DracoMesh> draco_meshes_;
  std::optional<Document> document_;
  std::pair<std::uint64_t, std::size_t> document_text_{};  // XXH3-64 and size of its text
};

// Decodes KHR_draco_mesh_compression data with libdraco, without a cache (core/draco.cpp).
FileResources::DracoMesh decode_draco_mesh(std::span<const std::uint8_t> compressed);

}  // namespace gltf_pbr
