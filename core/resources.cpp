#include "core/resources.hpp"

#include <xxhash.h>

#include "core/asset.hpp"

namespace gltf_pbr {

FileResources::FileResources(fs::path folder, bool allow_outside, bool keep_draco_meshes)
    : folder_(folder.empty() ? fs::path(".") : std::move(folder)),
      allow_outside_(allow_outside),
      keep_draco_meshes_(keep_draco_meshes) {}

const FileResources::External& FileResources::external(const std::string& uri) {
  const std::lock_guard lock(mutex_);
  if (const auto found = externals_.find(uri); found != externals_.end()) return found->second;
  External entry{resolve_uri(folder_, uri, allow_outside_), nullptr};
  if (entry.resolved.status == UriStatus::Readable) {
    ++work_counters().files_opened;
    if (auto mapped = MappedFile::open(entry.resolved.path, MappedFile::ReadAhead::OnTouch))
      entry.file = std::make_shared<const MappedFile>(std::move(*mapped));
  }
  return externals_.emplace(uri, std::move(entry)).first->second;
}

std::vector<fs::path> FileResources::files_read() const {
  const std::lock_guard lock(mutex_);
  std::vector<fs::path> files;
  for (const auto& [uri, entry] : externals_)
    if (entry.resolved.status == UriStatus::Readable) files.push_back(entry.resolved.path);
  return files;
}

FileResources::DracoMesh FileResources::draco_mesh(std::span<const std::uint8_t> compressed) {
  if (!keep_draco_meshes_) return decode_draco_mesh(compressed);
  const XXH128_hash_t hash = XXH3_128bits(compressed.data(), compressed.size());
  const std::pair<std::uint64_t, std::uint64_t> key{hash.high64, hash.low64};
  // Decoding runs under the lock: two steps asking for one mesh must not both decode it, and the
  // steps of one file ask one after another.
  const std::lock_guard lock(mutex_);
  if (const auto found = draco_meshes_.find(key); found != draco_meshes_.end()) return found->second;
  return draco_meshes_.emplace(key, decode_draco_mesh(compressed)).first->second;
}

namespace {
std::pair<std::uint64_t, std::size_t> fingerprint(std::span<const std::uint8_t> text) {
  return {XXH3_64bits(text.data(), text.size()), text.size()};
}
}  // namespace

void FileResources::keep_document(Document document, std::span<const std::uint8_t> text) {
  const std::lock_guard lock(mutex_);
  document_ = std::move(document);
  document_text_ = fingerprint(text);
}

std::optional<FileResources::Document> FileResources::take_document(std::span<const std::uint8_t> text) {
  const std::lock_guard lock(mutex_);
  std::optional<Document> taken;
  if (document_ && document_text_ == fingerprint(text)) taken = std::move(document_);
  document_.reset();
  return taken;
}

}  // namespace gltf_pbr
