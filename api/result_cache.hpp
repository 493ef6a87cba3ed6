// The results cache behind --cache DIR (issue 16). Every command is a pure function of the input's
// bytes, the files it references, its options, the rules and the tool's version (DESIGN.md, "Scale
// past one machine"), so a result is kept under a hash of all of them and a later run restores it,
// outputs and report entry, without loading the asset.
//
// DIR holds one format, v1, which several processes and machines may share:
//   v1/uris/<input digest>.json the external URIs the input names, so a lookup need not parse it
//   v1/digests/<ab>/<path hash> a file's digest with the identity and times it had then, so an
//                               unchanged input, resource or output in place is not read again
//   v1/entries/<ab>/<key>/      entry.json (the report entry and the list of files) and the files
//   v1/tmp/                     entries being written; each is renamed into entries/ whole, so a
//                               reader sees a complete entry or none, and the first writer wins
// Entries never change once written, and nothing is evicted: delete DIR to reclaim its space.
// Only results worth repeating are stored: a failed file is computed again on every run.
#pragma once
#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/files.hpp"

namespace gltf_pbr {

class ResultCache {
 public:
  // Creates the folder; throws OutputError naming it when that fails.
  explicit ResultCache(std::filesystem::path folder);

  // The key of the result that `settings` (the command and everything besides the files that it
  // depends on, as text) computes from `input`: XXH3-128 of the settings, the input's bytes and each
  // external file it names, resolved with the loader's path policy. A URI that is missing, or
  // outside the input's folder without `allow_outside`, enters the key as such and is not opened.
  // With `output_folder`, the input and each file it names that lie inside that folder enter the
  // key with their place in it: the names of a result's outputs avoid them. std::nullopt (counted
  // as a miss) when the input cannot be read or its URIs listed: that file is computed, not kept.
  std::optional<std::string> key(const std::filesystem::path& input, std::string_view settings, bool allow_outside,
                                 const std::filesystem::path& output_folder = {}) const;

  // Files a result wrote, each under `root`: an output folder, a preview folder.
  struct Outputs {
    std::filesystem::path root;
    std::vector<std::filesystem::path> files;
  };

  // The report entry stored under `key`, with its files written again under `roots` (the same
  // kinds of folder, in the same order, as when it was stored) in one atomic set; a file already
  // holding the same bytes is left alone. std::nullopt (a miss) when there is no entry or it is
  // damaged: unreadable, a file whose bytes no longer match their digest, a path outside its
  // root, or an entry `accept` refuses. A damaged entry is moved aside, so the result computed
  // instead takes its place. Throws OutputError when a file cannot be written.
  using Acceptance = std::function<bool(const nlohmann::json& entry)>;
  std::optional<nlohmann::json> restore(const std::string& key, std::span<const std::filesystem::path> roots,
                                        const Acceptance& accept = {});

  // Moves the entry under `key` aside: one restore() accepted that its caller could not use.
  void discard(const std::string& key);

  // Keeps `entry` and a copy of every output under `key`, unless a file the key was taken from
  // changed since (the result may be of other bytes). Never throws: a cache that cannot be written
  // costs the next run time, not this run its result, and is counted as not stored.
  void store(const std::string& key, const nlohmann::json& entry, std::span<const Outputs> outputs);
  // A result under `key` that is not to be kept (a failure, or one made without all its inputs):
  // counted as not stored, so that every miss is either stored or not.
  void leave_out(const std::string& key);

  // XXH3-128 of the file's bytes, as key() takes it for the files an input names: for inputs a
  // command takes besides the file (an environment map). Read only when the file's device, inode,
  // size or times differ from those recorded with its last digest; std::nullopt when unreadable.
  // `checked_signature`, when given, gets the signature the digest was checked against.
  // `contents`, when given, gets the file mapped if its bytes had to be read (for a caller that
  // reads them next); it stays empty when the record answered.
  std::optional<std::string> digest(const std::filesystem::path& file, std::string* checked_signature = nullptr,
                                    std::optional<MappedFile>* contents = nullptr) const;

  // {"folder", "hits", "misses", "stored", "notStored"} for the run's report; misses = stored +
  // notStored once every miss has been stored or left out.
  nlohmann::json stats_json() const;
  std::size_t hits() const { return hits_; }

  // A file a key was taken from: its signature (device, inode, size, times) and digest then.
  struct Source {
    std::filesystem::path file;
    std::string signature;
    std::string digest;
  };

 private:
  void remember(const std::filesystem::path& file, const std::string& digest) const;
  std::filesystem::path digest_record(const std::filesystem::path& file) const;
  std::filesystem::path entry_folder(const std::string& key) const;
  std::filesystem::path temporary_folder() const;  // a new, empty folder of its own in tmp/

  std::filesystem::path folder_;
  mutable std::atomic<std::size_t> hits_{0}, misses_{0}, stored_{0}, not_stored_{0};
  // The files each key of this run was taken from: rechecked before a store.
  mutable std::mutex sources_mutex_;
  mutable std::map<std::string, std::vector<Source>> sources_;
};

}  // namespace gltf_pbr
