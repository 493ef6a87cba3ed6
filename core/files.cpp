#include "core/files.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>

#include "core/error.hpp"

namespace gltf_pbr {

void check_failed(const char* expr, const std::string& operands, const char* where) {
  std::fprintf(stderr, "internal error: CHECK(%s) failed at %s: %s\n", expr, where, operands.c_str());
  std::abort();
}

std::optional<Bytes> read_file(const fs::path& path) {
  // A folder opens as a stream too, with a size no buffer can hold: only a regular file is read.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  struct stat status {};
  std::optional<Bytes> bytes;
  if (::fstat(fd, &status) == 0 && S_ISREG(status.st_mode)) {
    bytes.emplace(static_cast<size_t>(status.st_size));
    for (std::size_t at = 0; bytes && at < bytes->size();) {
      const ssize_t n = ::read(fd, bytes->data() + at, bytes->size() - at);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        bytes.reset();  // an error, or a file cut short while read
      else
        at += static_cast<std::size_t>(n);
    }
  }
  ::close(fd);
  return bytes;
}

std::string unreadable_reason(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::strerror(errno);
  struct stat status {};
  const bool regular = ::fstat(fd, &status) == 0 && S_ISREG(status.st_mode);
  ::close(fd);
  return regular ? "the read failed" : "not a regular file";
}

std::optional<MappedFile> MappedFile::open(const fs::path& path, ReadAhead read_ahead) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  struct stat status {};
  if (::fstat(fd, &status) != 0 || !S_ISREG(status.st_mode)) {
    ::close(fd);
    return std::nullopt;
  }
  const std::size_t size = static_cast<std::size_t>(status.st_size);
  void* data = size == 0 ? nullptr : ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);  // the mapping keeps the file
  if (data == MAP_FAILED) return std::nullopt;
  // Advice values are not flags (MADV_SEQUENTIAL | MADV_WILLNEED is MADV_WILLNEED): one call each.
  if (data && read_ahead == ReadAhead::Whole) {
    ::madvise(data, size, MADV_SEQUENTIAL);
    ::madvise(data, size, MADV_WILLNEED);
  }
  return MappedFile(static_cast<const std::uint8_t*>(data), size);
}

void MappedFile::release_pages() const {
  if (data_) ::madvise(const_cast<std::uint8_t*>(data_), size_, MADV_DONTNEED);
}

MappedFile::MappedFile(MappedFile&& other) noexcept : data_(other.data_), size_(other.size_) {
  other.data_ = nullptr;
  other.size_ = 0;
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<std::uint8_t*>(data_), size_);
}

namespace {

// Temporaries that exist right now, for the signal thread to remove (see install_signal_cleanup).
// Never destroyed: the signal thread may still walk it while static destructors run.
std::mutex temporaries_mutex;
std::set<std::string>& temporaries() {
  static auto* paths = new std::set<std::string>;
  return *paths;
}

// The pidfds of the children that may write into the temporaries (start_child), under the same lock.
std::set<int>& children() {
  static auto* pidfds = new std::set<int>;
  return *pidfds;
}

std::string errno_text(int error) { return std::strerror(error); }

// Creates a fresh temporary beside `destination` and records it, under one lock, so the signal
// thread (which exits holding that lock) never misses a file created while it cleans up. A name
// left by a killed earlier run (the same pid in a container) is skipped, not an error.
std::pair<int, fs::path> create_temporary(const fs::path& destination) {
  static std::atomic<unsigned> counter{0};
  static const unsigned process_salt = std::random_device{}();
  const std::lock_guard lock(temporaries_mutex);
  for (int attempt = 0;; ++attempt) {
    fs::path temporary = destination;
    temporary += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(process_salt % 100000) + "-" +
                 std::to_string(counter++);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      temporaries().insert(temporary.string());
      return {fd, temporary};
    }
    if (errno != EEXIST || attempt == 100) return {-errno, {}};
  }
}

void forget_temporary(const fs::path& path) {
  const std::lock_guard lock(temporaries_mutex);
  temporaries().erase(path.string());
}

}  // namespace

void install_signal_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    // The signals are blocked here, before any worker starts, so every thread inherits the mask and
    // only this one receives them: it can take the mutex, which a signal handler cannot. SIGPIPE is
    // ignored, so a closed pipe is a write error we report (exit 3), not a silent death.
    std::signal(SIGPIPE, SIG_IGN);
    sigset_t signals;
    sigemptyset(&signals);
    for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaddset(&signals, signal);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);
    std::thread([signals] {
      int received = 0;
      sigwait(&signals, &received);
      temporaries_mutex.lock();  // held until _Exit: no temporary is created after this pass
      // The children first: they would otherwise end only with this process (PR_SET_PDEATHSIG),
      // and one writing its report into a folder removed below would make the folder anew
      // (AtomicWriteSet creates a destination's folder). No child starts while the lock is held.
      std::vector<pollfd> running;
      for (const int pidfd : children()) {
        ::syscall(SYS_pidfd_send_signal, pidfd, SIGTERM, nullptr, 0);
        running.push_back({pidfd, POLLIN, 0});  // readable once the child has ended
      }
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
      while (!running.empty() && std::chrono::steady_clock::now() < deadline) {
        ::poll(running.data(), running.size(), 10);
        std::erase_if(running, [](const pollfd& wait) { return wait.revents != 0; });
      }
      // The run's own threads go on meanwhile: one removing a file from a folder as remove_all
      // walks it makes remove_all give up with ENOENT, so a folder is removed until it is gone.
      std::error_code ignored;
      for (const std::string& path : temporaries())
        for (int attempt = 0; attempt < 100 && fs::symlink_status(path, ignored).type() != fs::file_type::not_found;
             ++attempt)
          fs::remove_all(path, ignored);
      std::_Exit(128 + received);
    }).detach();
  });
}

int start_child(const std::function<int()>& spawn) {
  const std::lock_guard lock(temporaries_mutex);
  const int pidfd = spawn();
  if (pidfd >= 0) children().insert(pidfd);
  return pidfd;
}

void forget_child(int pidfd) {
  const std::lock_guard lock(temporaries_mutex);
  children().erase(pidfd);
}

TemporaryFolder::TemporaryFolder(const std::string& prefix) {
  std::string name = (fs::temp_directory_path() / (prefix + "XXXXXX")).string();
  const std::lock_guard lock(temporaries_mutex);  // as create_temporary: the signal thread sees it or it is not made
  if (!::mkdtemp(name.data())) {
    const int error = errno;
    throw OutputError("cannot create a temporary folder " + name + ": " + errno_text(error));
  }
  try {
    temporaries().insert(name);
  } catch (...) {
    ::rmdir(name.c_str());
    throw;
  }
  path_ = std::move(name);
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
  forget_temporary(path_);
}

bool writable_by_owner(const fs::path& path) {
  struct stat status {};
  return ::stat(path.c_str(), &status) == 0 && (status.st_mode & S_IWUSR) != 0;
}

std::string mode_text(const fs::path& path) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) return "unknown";
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(status.st_mode & 07777));
  return text;
}

AtomicWriteSet::~AtomicWriteSet() {
  std::error_code ignored;
  for (const auto& [temporary, destination] : staged_) {
    if (temporary.empty()) continue;
    fs::remove(temporary, ignored);
    forget_temporary(temporary);
  }
}

// The descriptor a name stands for when it names one of this process's own (/dev/stdout,
// /dev/stderr, /dev/fd/N, /proc/self/fd/N): what the shell opened, a file appended to included.
std::optional<int> own_descriptor(const fs::path& name) {
  std::error_code ec;
  const std::string path = fs::absolute(name, ec).lexically_normal().string();
  if (path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  for (const std::string_view prefix : {"/dev/fd/", "/proc/self/fd/"}) {
    if (!path.starts_with(prefix) || path.size() == prefix.size() || path.size() > prefix.size() + 9) continue;
    const std::string digits = path.substr(prefix.size());
    if (digits.find_first_not_of("0123456789") == std::string::npos) return std::stoi(digits);
  }
  return std::nullopt;
}

void AtomicWriteSet::stage(const fs::path& destination, std::span<const std::uint8_t> bytes) {
  std::error_code ec;
  const std::optional<int> descriptor = own_descriptor(destination);
  const fs::file_status target = fs::status(destination, ec);  // through links
  if (descriptor || (fs::exists(target) && !fs::is_regular_file(target) && !fs::is_directory(target))) {
    written_into_.push_back({destination, descriptor.value_or(-1), {bytes.begin(), bytes.end()}});
    return;
  }
  // Renaming over a link would take away the file it named from whatever reads it; writing through
  // it may replace a file the run reads, or one it writes under another name.
  if (fs::is_symlink(fs::symlink_status(destination, ec)))
    throw OutputError("cannot write " + destination.string() + ": it is a symbolic link (to " +
                      fs::read_symlink(destination, ec).string() + "); name the file itself, or remove the link");
  if (!destination.parent_path().empty() && !fs::create_directories(destination.parent_path(), ec) && ec)
    throw OutputError("cannot create the folder " + destination.parent_path().string() + ": " + ec.message());
  auto fail = [&](int error) { throw OutputError("cannot write " + destination.string() + ": " + errno_text(error)); };
  const auto [fd, temporary] = create_temporary(destination);
  if (fd < 0) fail(-fd);
  int error = 0;
  for (std::size_t written = 0; written < bytes.size() && error == 0;) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno != EINTR) error = errno;
    if (n > 0) written += static_cast<std::size_t>(n);
  }
  // A file being replaced keeps its mode and, where we may, its owner (root replacing a user's file).
  struct stat existing {};
  if (error == 0 && ::stat(destination.c_str(), &existing) == 0) {
    if (::fchown(fd, existing.st_uid, existing.st_gid) != 0)
      (void)::fchown(fd, static_cast<uid_t>(-1), existing.st_gid);
    if (::fchmod(fd, existing.st_mode & 07777) != 0) error = errno;
  }
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) {
    ::unlink(temporary.c_str());
    forget_temporary(temporary);
    fail(error);
  }
  staged_.emplace_back(temporary, destination);
}

std::vector<fs::path> AtomicWriteSet::commit() {
  // How each destination was written, so that a later failure can undo it: a file that did not
  // exist is removed; one that did is exchanged with the new one (renameat2 RENAME_EXCHANGE, Linux
  // 3.15), so its old bytes wait under the temporary name until the commit ends. A file system
  // that cannot exchange names gets a plain rename, which cannot be undone.
  enum class Placed { Created, Exchanged, Replaced };
  std::vector<std::pair<size_t, Placed>> done;  // (index in staged_, how)
  // Undoes what `done` placed; names any old file that could not go back where it was.
  const auto undo = [&] {
    std::string kept;
    for (auto it = done.rbegin(); it != done.rend(); ++it) {
      auto& [temporary, destination] = staged_[it->first];
      std::error_code ec;
      if (it->second == Placed::Created) fs::remove(destination, ec);
      if (it->second != Placed::Exchanged) continue;
      fs::rename(temporary, destination, ec);
      if (ec) {  // its only copy: kept, not removed with the temporaries
        kept += "; the earlier " + destination.string() + " is kept as " + temporary.string();
        forget_temporary(temporary);
        temporary.clear();
      }
    }
    return kept;
  };
  for (size_t k = 0; k < staged_.size(); ++k) {
    auto& [temporary, destination] = staged_[k];
    std::error_code ec;
    const fs::file_type type = fs::symlink_status(destination, ec).type();
    // Only a file is exchanged: a folder in the way must fail the rename, not move aside.
    Placed placed = type == fs::file_type::not_found                                   ? Placed::Created
                    : type == fs::file_type::regular || type == fs::file_type::symlink ? Placed::Exchanged
                                                                                       : Placed::Replaced;
    int result = placed == Placed::Replaced
                     ? ::rename(temporary.c_str(), destination.c_str())
                     : ::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, destination.c_str(),
                                   placed == Placed::Exchanged ? RENAME_EXCHANGE : RENAME_NOREPLACE);
    if (result != 0 && placed != Placed::Replaced &&
        (errno == EINVAL || errno == ENOSYS || errno == EEXIST || errno == ENOENT)) {
      // No renameat2 flags on this file system, or the destination came or went meanwhile: a plain
      // rename, which creates or replaces it as it now stands.
      placed =
          fs::symlink_status(destination, ec).type() == fs::file_type::not_found ? Placed::Created : Placed::Replaced;
      result = ::rename(temporary.c_str(), destination.c_str());
    }
    if (result != 0) {
      const int error = errno;
      const std::string kept = undo();
      throw OutputError("cannot rename into " + destination.string() + ": " + errno_text(error) + kept);
    }
    done.emplace_back(k, placed);
    if (placed != Placed::Exchanged) forget_temporary(temporary), temporary.clear();
  }
  std::vector<fs::path> written;
  for (const auto& [k, placed] : done) {
    if (placed == Placed::Exchanged) {  // the old bytes, no longer needed
      ::unlink(staged_[k].first.c_str());
      forget_temporary(staged_[k].first);
    }
    written.push_back(staged_[k].second);
  }
  staged_.clear();
  for (const WrittenInto& into : written_into_) {
    // Opened without truncation; a pipe's open waits for its reader, as a shell's redirection does.
    const int fd = into.descriptor >= 0 ? into.descriptor : ::open(into.destination.c_str(), O_WRONLY | O_CLOEXEC);
    int error = fd < 0 ? errno : 0;
    for (std::size_t at = 0; at < into.bytes.size() && error == 0;) {
      const ssize_t n = ::write(fd, into.bytes.data() + at, into.bytes.size() - at);
      if (n < 0 && errno != EINTR) error = errno;
      if (n > 0) at += static_cast<std::size_t>(n);
    }
    if (fd >= 0 && into.descriptor < 0 && ::close(fd) != 0 && error == 0) error = errno;
    if (error != 0) throw OutputError("cannot write " + into.destination.string() + ": " + errno_text(error));
    written.push_back(into.destination);
  }
  written_into_.clear();
  return written;
}

std::string percent_decode(const std::string& uri) {
  std::string out;
  out.reserve(uri.size());
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

bool is_data_uri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

std::optional<Bytes> decode_data_uri(const std::string& uri, std::string* mime_type) {
  const size_t comma = uri.find(',');
  if (!is_data_uri(uri) || comma == std::string::npos) return std::nullopt;
  const std::string header = uri.substr(5, comma - 5);
  const size_t base64_marker = header.rfind(";base64");
  if (base64_marker == std::string::npos || base64_marker + 7 != header.size()) return std::nullopt;
  if (mime_type) *mime_type = header.substr(0, base64_marker);
  return decode_base64(std::string_view(uri).substr(comma + 1));
}

std::optional<Bytes> decode_base64(std::string_view text, Base64Problem* problem) {
  using Kind = Base64Problem::Kind;
  auto fail = [&](Kind kind, std::size_t at) -> std::optional<Bytes> {
    if (problem) *problem = {kind, at};
    return std::nullopt;
  };
  Bytes out;
  out.reserve(text.size() / 4 * 3);
  std::uint32_t accumulator = 0;
  int bits = 0;
  std::size_t first_padding = std::string_view::npos;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '=') {
      if (first_padding == std::string_view::npos) first_padding = i;
      if (i - first_padding >= 2) return fail(Kind::PaddingTooLong, first_padding);
      continue;
    }
    int value;
    if (c >= 'A' && c <= 'Z')
      value = c - 'A';
    else if (c >= 'a' && c <= 'z')
      value = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      value = c - '0' + 52;
    else if (c == '+' || c == '-')
      value = 62;
    else if (c == '/' || c == '_')
      value = 63;
    else
      return fail(Kind::Character, i);
    if (first_padding != std::string_view::npos) return fail(Kind::PaddingNotAtEnd, first_padding);
    accumulator = (accumulator << 6) | static_cast<std::uint32_t>(value);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((accumulator >> bits) & 0xFF));
    }
  }
  // RFC 4648 section 3.2: padding fills the last quantum, so a padded text is whole quanta; an
  // unpadded one may end two or three characters into one, never one (6 bits make no byte).
  if (first_padding != std::string_view::npos && text.size() % 4 != 0) return fail(Kind::PaddedLength, text.size());
  if (first_padding == std::string_view::npos && text.size() % 4 == 1) return fail(Kind::Length, text.size());
  return out;
}

ResolvedUri resolve_uri(const fs::path& asset_folder, const std::string& uri, bool allow_outside) {
  auto refused = [](std::string why) { return ResolvedUri{UriStatus::Refused, {}, std::move(why)}; };
  if (uri.empty()) return {UriStatus::NotFound, {}, "empty URI"};
  const size_t colon = uri.find(':');
  const size_t slash = uri.find('/');
  if (colon != std::string::npos && (slash == std::string::npos || colon < slash))
    return refused("URI '" + uri + "' has a scheme; only relative file paths and data URIs are read");
  const fs::path relative = percent_decode(uri);
  if (relative.is_absolute() && !allow_outside)
    return refused("URI '" + uri + "' is an absolute path (pass --allow-outside-uris to read it)");
  // A bare file name on the command line has an empty parent: that folder is ".".
  const fs::path folder = asset_folder.empty() ? fs::path(".") : asset_folder;
  const fs::path resolved = (folder / relative).lexically_normal();
  std::error_code ec;
  if (!allow_outside) {
    // weakly_canonical follows symlinks, so a link inside the folder to a file outside is refused
    // too. A path it cannot resolve (a loop, a name too long, a folder we may not enter) is refused.
    const fs::path root = fs::weakly_canonical(fs::absolute(folder, ec), ec);
    if (ec) return refused("URI '" + uri + "': the asset's folder cannot be resolved (" + ec.message() + ")");
    const fs::path target = fs::weakly_canonical(fs::absolute(resolved, ec), ec);
    if (ec) return refused("URI '" + uri + "' cannot be resolved (" + ec.message() + ")");
    const auto [root_end, ignored] = std::mismatch(root.begin(), root.end(), target.begin(), target.end());
    if (root.empty() || root_end != root.end())
      return refused("URI '" + uri + "' points outside the asset's folder (pass --allow-outside-uris to read it)");
  }
  if (!fs::is_regular_file(resolved, ec)) return {UriStatus::NotFound, {}, "file not found: '" + uri + "'"};
  return {UriStatus::Readable, resolved, {}};
}

}  // namespace gltf_pbr
