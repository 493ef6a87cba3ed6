#include "api/result_cache.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>

#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/files.hpp"

namespace gltf_pbr {
namespace {

constexpr char kFormat[] = "v1";

std::string hex(XXH128_hash_t hash) {
  char text[33];
  std::snprintf(text, sizeof text, "%016llx%016llx", static_cast<unsigned long long>(hash.high64),
                static_cast<unsigned long long>(hash.low64));
  return text;
}

std::span<const std::uint8_t> bytes_of(const std::string& text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

// A stored file's path: relative, inside its root, and spelled as we wrote it. Anything else came
// from a damaged or foreign entry, and is never written.
bool is_plain_relative(const fs::path& path) {
  if (path.empty() || path.is_absolute() || path != path.lexically_normal()) return false;
  for (const fs::path& part : path)
    if (part == ".." || part == ".") return false;
  return true;
}

XXH128_hash_t hash_of(std::string_view text) { return XXH3_128bits(text.data(), text.size()); }

// The file's identity and times, as text: what says it is still the file a digest was taken of.
std::optional<std::string> signature(const fs::path& file, std::int64_t* changed_ns = nullptr) {
  struct stat status {};
  if (::stat(file.c_str(), &status) != 0 || !S_ISREG(status.st_mode)) return std::nullopt;
  const auto ns = [](const timespec& t) { return std::int64_t{t.tv_sec} * 1'000'000'000 + t.tv_nsec; };
  if (changed_ns) *changed_ns = std::max(ns(status.st_mtim), ns(status.st_ctim));
  char text[128];
  std::snprintf(text, sizeof text, "%llu %llu %lld %lld %lld", static_cast<unsigned long long>(status.st_dev),
                static_cast<unsigned long long>(status.st_ino), static_cast<long long>(status.st_size),
                static_cast<long long>(ns(status.st_mtim)), static_cast<long long>(ns(status.st_ctim)));
  return text;
}

std::int64_t now_ns() {
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  return std::int64_t{now.tv_sec} * 1'000'000'000 + now.tv_nsec;
}

// XXH3-128 of a file's bytes, read in blocks (a mapping costs a page fault per page).
std::optional<std::string> hash_file(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  XXH3_state_t* state = XXH3_createState();
  XXH3_128bits_reset(state);
  std::vector<char> block(1 << 20);
  ssize_t n = 0;
  while ((n = ::read(fd, block.data(), block.size())) > 0 || (n < 0 && errno == EINTR))
    if (n > 0) XXH3_128bits_update(state, block.data(), static_cast<std::size_t>(n));
  ::close(fd);
  const std::string digest = hex(XXH3_128bits_digest(state));
  XXH3_freeState(state);
  if (n < 0) return std::nullopt;
  return digest;
}

// Whether a file still holds the bytes a key was taken of. A signature that differs only in its
// status-change time (a hard link made or removed elsewhere, a chmod) is settled by reading the
// bytes again; a new device, inode, size or modification time is a change. The trade-off: a file
// rewritten in place during the run and then written back to its first bytes, size and
// modification time (cp -p, touch -r) passes, though the run may have read the bytes between.
// Refusing every status change instead left results unstored whenever another job linked the
// same file (a library of hard links, as tests/pipeline/make_library.py makes).
bool unchanged_since_key(const ResultCache::Source& source) {
  const std::optional<std::string> now = signature(source.file);
  if (!now) return false;
  if (*now == source.signature) return true;
  const auto without_ctime = [](std::string_view text) { return text.substr(0, text.rfind(' ')); };
  return without_ctime(*now) == without_ctime(source.signature) && hash_file(source.file) == source.digest;
}

// The URIs an input names, from the index when an earlier run listed them, else from its JSON:
// `contents`, the mapping the digest hashed, or the file read again here. Listed (and indexed)
// only when the bytes still hash as `input_hash` after they are parsed (a mapping is no snapshot).
std::optional<std::vector<std::string>> uris_of(const fs::path& index, const fs::path& input,
                                                const std::string& input_hash,
                                                const std::optional<MappedFile>& contents) {
  if (const std::optional<Bytes> listed = read_file(index)) {
    try {
      return nlohmann::json::parse(listed->begin(), listed->end()).get<std::vector<std::string>>();
    } catch (const nlohmann::json::exception&) {
      // a damaged index is listed again below and replaced
    }
  }
  std::optional<Bytes> read;
  if (!contents) {
    read = read_file(input);
    if (!read) return std::nullopt;
    ++work_counters().documents_read;
  }
  const std::span<const std::uint8_t> bytes = contents ? contents->bytes() : std::span<const std::uint8_t>(*read);
  std::optional<std::vector<std::string>> uris = external_uris(bytes);
  if (hex(XXH3_128bits(bytes.data(), bytes.size())) != input_hash) return std::nullopt;  // changed
  if (uris) try {
      AtomicWriteSet file;
      file.stage(index, bytes_of(nlohmann::json(*uris).dump()));
      file.commit();
    } catch (const OutputError&) {
      // an index not written is listed again next time
    }
  return uris;
}

bool is_inside(const fs::path& file, const fs::path& folder, fs::path* relative) {
  std::error_code error;
  const fs::path canonical = fs::weakly_canonical(file, error);
  if (error) return false;
  *relative = canonical.lexically_relative(folder);
  return is_plain_relative(*relative);
}

}  // namespace

ResultCache::ResultCache(fs::path folder) : folder_(std::move(folder)) {
  std::error_code error;
  fs::create_directories(folder_ / kFormat / "tmp", error);
  if (error || !fs::is_directory(folder_ / kFormat / "tmp"))
    throw OutputError("cannot create the cache folder " + folder_.string() + ": " + error.message());
}

fs::path ResultCache::digest_record(const fs::path& file) const {
  const std::string name = hex(hash_of(fs::absolute(file).lexically_normal().string()));
  return folder_ / kFormat / "digests" / name.substr(0, 2) / name;
}

fs::path ResultCache::entry_folder(const std::string& key) const {
  return folder_ / kFormat / "entries" / key.substr(0, 2) / key;
}

fs::path ResultCache::temporary_folder() const {
  // mkdtemp's random name: unique across the processes and machines that share the folder.
  std::string name = (folder_ / kFormat / "tmp" / "entry-XXXXXX").string();
  if (!::mkdtemp(name.data())) throw std::system_error(errno, std::generic_category(), "mkdtemp");
  return name;
}

std::optional<std::string> ResultCache::digest(const fs::path& file, std::string* checked_signature,
                                               std::optional<MappedFile>* contents) const {
  std::int64_t changed = 0;
  const std::optional<std::string> now = signature(file, &changed);
  if (!now) return std::nullopt;
  // Taken before the bytes are read: a write after it shows as a changed signature at store().
  if (checked_signature) *checked_signature = *now;
  if (const std::optional<Bytes> record = read_file(digest_record(file))) {
    // "<signature>\n<digest> <recorded at, ns>": trusted only when the file last changed more
    // than a second before it was recorded. A write within the same timestamp tick as the
    // recording would leave the times as they were ("racy git"): such a file is read again.
    const std::string text(record->begin(), record->end());
    const std::size_t line = text.find('\n'), space = text.rfind(' ');
    if (line != std::string::npos && space != std::string::npos && space > line && text.compare(0, line, *now) == 0) {
      const std::int64_t recorded = std::strtoll(text.c_str() + space + 1, nullptr, 10);
      if (changed < recorded - 1'000'000'000) return text.substr(line + 1, space - line - 1);
    }
  }
  std::optional<std::string> hash;
  if (std::optional<MappedFile> mapped = contents ? MappedFile::open(file) : std::nullopt) {
    hash = hex(XXH3_128bits(mapped->bytes().data(), mapped->bytes().size()));  // as hash_file's blocks add up
    contents->emplace(std::move(*mapped));  // for the caller, who reads the file next
  } else {
    hash = hash_file(file);
  }
  if (contents && hash) ++work_counters().documents_read;  // an input's own bytes (key()), mapped or hashed
  if (hash) remember(file, *hash);
  return hash;
}

void ResultCache::remember(const fs::path& file, const std::string& hash) const {
  const std::optional<std::string> now = signature(file);
  if (!now) return;
  try {
    AtomicWriteSet record;
    record.stage(digest_record(file), bytes_of(*now + "\n" + hash + " " + std::to_string(now_ns())));
    record.commit();
  } catch (const OutputError&) {
    // not recorded: read again next time
  }
}

std::optional<std::string> ResultCache::key(const fs::path& input, std::string_view settings, bool allow_outside,
                                            const fs::path& output_folder) const {
  std::string input_signature;
  std::optional<MappedFile> input_bytes;  // mapped by the digest when it has no record of the file
  const std::optional<std::string> input_hash = digest(input, &input_signature, &input_bytes);
  const std::optional<std::vector<std::string>> uris =
      input_hash ? uris_of(folder_ / kFormat / "uris" / (*input_hash + ".json"), input, *input_hash, input_bytes)
                 : std::nullopt;
  if (!uris) {  // no key: a miss that cannot be kept
    ++misses_;
    ++not_stored_;
    return std::nullopt;
  }
  std::error_code error;
  const fs::path outputs = output_folder.empty() ? fs::path() : fs::weakly_canonical(output_folder, error);
  std::vector<Source> sources;  // what the key is of
  XXH3_state_t* state = XXH3_createState();
  if (!state) throw std::bad_alloc();
  XXH3_128bits_reset(state);
  const auto add = [&](std::string_view text) {
    XXH3_128bits_update(state, text.data(), text.size());
    XXH3_128bits_update(state, "", 1);  // a separator no text holds
  };
  const auto add_place = [&](const fs::path& file) {  // where an output could take its name
    fs::path relative;
    if (!outputs.empty() && is_inside(file, outputs, &relative))
      add("inside the output folder: " + relative.generic_string());
  };
  add("gltf-pbr results cache");
  add(kFormat);
  add(settings);
  add(*input_hash);
  sources.push_back({input, input_signature, *input_hash});
  add_place(input);
  const fs::path folder = input.parent_path().empty() ? fs::path(".") : input.parent_path();
  for (const std::string& uri : *uris) {
    add(uri);
    const ResolvedUri resolved = resolve_uri(folder, uri, allow_outside);
    std::string resource_signature;
    const std::optional<std::string> hash =
        resolved.status == UriStatus::Readable ? digest(resolved.path, &resource_signature) : std::nullopt;
    add(hash                                     ? *hash
        : resolved.status == UriStatus::Refused  ? "refused"
        : resolved.status == UriStatus::NotFound ? "missing"
                                                 : "unreadable");
    if (hash) {
      sources.push_back({resolved.path, resource_signature, *hash});
      add_place(resolved.path);
    }
  }
  const std::string key = hex(XXH3_128bits_digest(state));
  XXH3_freeState(state);
  std::lock_guard lock(sources_mutex_);
  sources_[key] = std::move(sources);
  return key;
}

void ResultCache::discard(const std::string& key) {
  std::error_code error;
  try {
    const fs::path aside = temporary_folder();
    // A rename, so no reader sees the entry half gone; then it goes.
    fs::rename(entry_folder(key), aside / "discarded", error);
    fs::remove_all(aside, error);
  } catch (const std::exception&) {
    // left in place: the next run meets it again
  }
}

std::optional<nlohmann::json> ResultCache::restore(const std::string& key, std::span<const fs::path> roots,
                                                   const Acceptance& accept) {
  const fs::path folder = entry_folder(key);
  const std::optional<Bytes> text = read_file(folder / "entry.json");
  if (!text) {
    std::error_code error;
    if (fs::exists(folder, error)) discard(key);  // a folder without its entry: never whole
    ++misses_;
    return std::nullopt;
  }
  std::vector<MappedFile> blobs;                           // kept mapped until the set is committed
  std::vector<std::pair<fs::path, std::string>> restored;  // (destination, digest) of files written
  AtomicWriteSet files;
  nlohmann::json entry;
  try {
    const nlohmann::json stored = nlohmann::json::parse(text->begin(), text->end());
    entry = stored.at("entry");
    if (accept && !accept(entry)) throw std::invalid_argument("an entry its command does not take");
    const nlohmann::json& listed = stored.at("files");
    for (std::size_t i = 0; i < listed.size(); ++i) {
      const auto root = listed[i].at("root").get<std::size_t>();
      const fs::path path = listed[i].at("path").get<std::string>();
      const std::string hash = listed[i].at("digest").get<std::string>();
      if (root >= roots.size() || roots[root].empty() || !is_plain_relative(path))
        throw std::invalid_argument("a file outside its root");
      const fs::path destination = roots[root] / path;
      if (digest(destination) == hash) continue;  // already there, as a rerun into the same folder finds it
      std::optional<MappedFile> blob = MappedFile::open(folder / std::to_string(i));
      if (!blob || hex(XXH3_128bits(blob->bytes().data(), blob->bytes().size())) != hash)
        throw std::invalid_argument("a file missing or changed");
      blobs.push_back(std::move(*blob));
      files.stage(destination, blobs.back().bytes());
      restored.emplace_back(destination, hash);
    }
  } catch (const OutputError&) {
    throw;
  } catch (const std::exception&) {  // damaged or foreign: never trusted, and replaced
    discard(key);
    ++misses_;
    return std::nullopt;
  }
  files.commit();
  for (const auto& [destination, hash] : restored) remember(destination, hash);
  ++hits_;
  return entry;
}

void ResultCache::store(const std::string& key, const nlohmann::json& entry, std::span<const Outputs> outputs) {
  std::vector<Source> sources;
  {
    std::lock_guard lock(sources_mutex_);
    if (const auto it = sources_.find(key); it != sources_.end()) sources = std::move(it->second), sources_.erase(it);
  }
  // A file that changed since its key was taken may have been read as other bytes: not kept.
  if (sources.empty() || !std::all_of(sources.begin(), sources.end(), unchanged_since_key)) {
    ++not_stored_;
    return;
  }
  std::error_code error;
  fs::path temporary;
  try {
    temporary = temporary_folder();
    nlohmann::json files = nlohmann::json::array();
    for (std::size_t root = 0; root < outputs.size(); ++root)
      for (const fs::path& file : outputs[root].files) {
        const fs::path relative = file.lexically_relative(outputs[root].root);
        if (!is_plain_relative(relative)) throw std::invalid_argument("an output outside its folder");
        const fs::path blob = temporary / std::to_string(files.size());
        fs::copy_file(file, blob);
        const std::optional<std::string> hash = hash_file(blob);
        if (!hash) throw std::invalid_argument("cannot read a copied output");
        remember(file, *hash);  // the next run finds the output in place without reading it
        files.push_back({{"root", root}, {"path", relative.generic_string()}, {"digest", *hash}});
      }
    const std::string text = nlohmann::json{{"entry", entry}, {"files", files}}.dump(
        -1, ' ', false, nlohmann::json::error_handler_t::replace);
    AtomicWriteSet written;
    written.stage(temporary / "entry.json", bytes_of(text));
    written.commit();
    fs::create_directories(entry_folder(key).parent_path());
    // rename(2) of a folder onto a non-empty one fails: another process stored the same result first.
    if (std::rename(temporary.c_str(), entry_folder(key).c_str()) == 0)
      ++stored_;
    else if (errno == EEXIST || errno == ENOTEMPTY)
      ++not_stored_;
    else
      throw std::system_error(errno, std::generic_category());
    fs::remove_all(temporary, error);
  } catch (const std::exception&) {
    if (!temporary.empty()) fs::remove_all(temporary, error);
    ++not_stored_;
  }
}

void ResultCache::leave_out(const std::string& key) {
  std::lock_guard lock(sources_mutex_);
  sources_.erase(key);
  ++not_stored_;
}

nlohmann::json ResultCache::stats_json() const {
  return {{"folder", folder_.string()},
          {"hits", hits_.load()},
          {"misses", misses_.load()},
          {"stored", stored_.load()},
          {"notStored", not_stored_.load()}};
}

}  // namespace gltf_pbr
