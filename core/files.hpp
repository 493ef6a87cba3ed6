// File-system helpers: whole-file reads, atomic writes, and URI resolution inside an asset's folder.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gltf_pbr {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

// Reads a whole file; std::nullopt when it cannot be opened.
std::optional<Bytes> read_file(const fs::path& path);

// Why `path` cannot be read, in the system's words ("No such file or directory", "Permission
// denied", "not a regular file"), for the message of a read that failed.
std::string unreadable_reason(const fs::path& path);

// A whole file mapped read-only, for readers that only look: no copy and no zero-filled buffer,
// the pages come straight from the page cache (validating a 224 MB GLB saves ~0.1 s). The file
// must not shrink while mapped (as with any mmap reader).
class MappedFile {
 public:
  // Whether the kernel should start reading the whole file now (a reader about to go through it)
  // or only the pages that are touched (an image that a step may never decode).
  enum class ReadAhead { Whole, OnTouch };
  // std::nullopt when the file cannot be opened or mapped.
  static std::optional<MappedFile> open(const fs::path& path, ReadAhead read_ahead = ReadAhead::Whole);
  MappedFile(MappedFile&& other) noexcept;
  MappedFile& operator=(MappedFile&&) = delete;
  MappedFile(const MappedFile&) = delete;
  ~MappedFile();
  std::span<const std::uint8_t> bytes() const { return {data_, size_}; }
  // Drops this process's copies of the pages read so far (they stay in the page cache, and a later
  // read maps them again): a reader done with the file gives its memory back.
  void release_pages() const;

 private:
  MappedFile(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

// A set of files written to temporary names and renamed into place only by commit(),
// so a failure never leaves partial output. Destroying it without commit() removes the temporaries,
// and so does SIGINT or SIGTERM arriving while they exist. A file that replaces an existing one
// keeps that file's mode and, where permitted, its owner and group. A device, pipe or socket
// (/dev/null, a FIFO) cannot be replaced: it is written into, after the renames, and a name of one
// of this process's descriptors (/dev/stdout, /proc/self/fd/1) into that descriptor, at its offset.
// A symbolic link is refused: renamed over, it would no longer lead to its file; written through,
// it might lead to a file the run reads.
// The descriptor a name stands for when it names one of this process's own (/dev/stdout,
// /dev/stderr, /dev/fd/N, /proc/self/fd/N); std::nullopt for any other name.
std::optional<int> own_descriptor(const fs::path& name);

class AtomicWriteSet {
 public:
  AtomicWriteSet() = default;
  AtomicWriteSet(const AtomicWriteSet&) = delete;
  AtomicWriteSet& operator=(const AtomicWriteSet&) = delete;
  ~AtomicWriteSet();
  // Throws OutputError naming the destination and errno's reason when the temporary cannot be written.
  void stage(const fs::path& destination, std::span<const std::uint8_t> bytes);
  // Renames every staged file into place, in staging order; returns their destinations. When a
  // rename fails, the files already renamed are put back as they were before the commit (a new
  // one removed, a replaced one restored where the file system can exchange two names) and the
  // OutputError is thrown.
  std::vector<fs::path> commit();

 private:
  std::vector<std::pair<fs::path, fs::path>> staged_;  // (temporary, destination)
  struct WrittenInto {
    fs::path destination;
    int descriptor;  // this process's own, or -1: opened by name
    std::vector<std::uint8_t> bytes;
  };
  std::vector<WrittenInto> written_into_;
};

// A private folder under the system's temporary directory (TMPDIR), named `prefix` and six random
// characters, removed with its contents when this ends or when the run is interrupted (see
// install_signal_cleanup). Throws OutputError when it cannot be created.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& prefix);
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  ~TemporaryFolder();
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// A child process that may write into this run's temporaries (convert --isolate's children write
// their reports into a TemporaryFolder): `spawn` starts it and returns its pidfd (pidfd_open), or
// -1, under the cleanup's lock, and the pidfd is recorded. Call forget_child(pidfd) once the child
// is reaped, before closing the pidfd.
int start_child(const std::function<int()>& spawn);
void forget_child(int pidfd);

// Starts the thread that, on SIGINT or SIGTERM, stops the recorded children (SIGTERM, then up to a
// second for them to end: a child's own cleanup removes its temporaries, and one still running
// would make a removed folder anew), removes every AtomicWriteSet temporary and every
// TemporaryFolder, and exits with 128 + the signal. Call it first thing in main, before any other
// thread exists.
void install_signal_cleanup();

// Whether the file's mode lets its owner write it (the mode bits, not access(2): root may write anything).
bool writable_by_owner(const fs::path& path);
// The file's permission bits in octal ("0644"), for messages.
std::string mode_text(const fs::path& path);

// Percent-decodes a URI path (RFC 3986 section 2.1).
std::string percent_decode(const std::string& uri);

bool is_data_uri(const std::string& uri);
// Decodes "data:<mime>;base64,<payload>"; std::nullopt when the payload is not valid base64.
std::optional<Bytes> decode_data_uri(const std::string& uri, std::string* mime_type = nullptr);
// Decodes base64 as glTF validators take it (RFC 4648): the standard alphabet (section 4) or the
// URL- and filename-safe one (section 5); '=' padding may be left out, but when present it ends the
// text and completes its last quantum (section 3.2), and an unpadded text never ends one character
// into a quantum. std::nullopt when the text is not base64, with `problem` saying why and where.
struct Base64Problem {
  enum class Kind {
    Character,        // not in either alphabet
    PaddingNotAtEnd,  // '=' followed by data
    PaddingTooLong,   // more than two '='
    PaddedLength,     // padded, but not whole quanta
    Length,           // unpadded, one character into a quantum
  };
  Kind kind = Kind::Character;
  std::size_t at = 0;  // index of the character at fault (the first '=' for padding); the size for lengths
};
std::optional<Bytes> decode_base64(std::string_view text, Base64Problem* problem = nullptr);

// The one path policy for every URI a command reads (buffers, images; convert, validate, preview):
// percent-decoded (RFC 3986 2.1), relative to the asset's folder; schemes are never read; absolute
// paths and paths that leave the folder, through ".." or a symlink, are refused unless allow_outside.
// A refused URI's file is never opened, not even to see whether it exists.
enum class UriStatus { Readable, NotFound, Refused };
struct ResolvedUri {
  UriStatus status = UriStatus::NotFound;
  fs::path path;        // the file to read when Readable
  std::string problem;  // why not, for NotFound and Refused
};
ResolvedUri resolve_uri(const fs::path& folder, const std::string& uri, bool allow_outside);

}  // namespace gltf_pbr
