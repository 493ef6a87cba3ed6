#include "core/files.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "core/error.hpp"

namespace gltf_pbr {

void check_failed(const char* expr, const std::string& operands, const char* where) {
  std::fprintf(stderr, "internal error: CHECK(%s) failed at %s: %s\n", expr, where, operands.c_str());
  std::abort();
}

std::optional<Bytes> read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return std::nullopt;
  const std::streamsize size = in.tellg();
  if (size < 0) return std::nullopt;
  Bytes bytes(static_cast<size_t>(size));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), size)) return std::nullopt;
  return bytes;
}

std::optional<MappedFile> MappedFile::open(const fs::path& path) {
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
  if (data) ::madvise(data, size, MADV_SEQUENTIAL | MADV_WILLNEED);
  return MappedFile(static_cast<const std::uint8_t*>(data), size);
}

MappedFile::MappedFile(MappedFile&& other) noexcept : data_(other.data_), size_(other.size_) {
  other.data_ = nullptr;
  other.size_ = 0;
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<std::uint8_t*>(data_), size_);
}

AtomicWriteSet::~AtomicWriteSet() {
  std::error_code ignored;
  for (const auto& [temporary, destination] : staged_) fs::remove(temporary, ignored);
}

void AtomicWriteSet::stage(const fs::path& destination, std::span<const std::uint8_t> bytes) {
  static std::atomic<unsigned> counter{0};
  fs::path temporary = destination;
  temporary += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  std::error_code ec;
  if (!destination.parent_path().empty()) fs::create_directories(destination.parent_path(), ec);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (out) out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out || !out.flush()) {
      out.close();
      fs::remove(temporary, ec);
      throw std::runtime_error("cannot write " + destination.string());
    }
  }
  staged_.emplace_back(temporary, destination);
}

void AtomicWriteSet::commit() {
  for (auto& [temporary, destination] : staged_) {
    std::error_code ec;
    fs::rename(temporary, destination, ec);
    if (ec) throw std::runtime_error("cannot rename into " + destination.string() + ": " + ec.message());
    temporary.clear();
  }
  staged_.clear();
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
  // RFC 4648 section 4 alphabet, '=' padding only at the end.
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  Bytes out;
  out.reserve((uri.size() - comma) * 3 / 4);
  unsigned accumulator = 0;
  int bits = 0;
  size_t padding = 0;
  for (size_t i = comma + 1; i < uri.size(); ++i) {
    const char c = uri[i];
    if (c == '=') {
      ++padding;
      continue;
    }
    const int v = value(c);
    if (v < 0 || padding > 0) return std::nullopt;
    accumulator = (accumulator << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((accumulator >> bits) & 0xFF));
    }
  }
  if (padding > 2 || (uri.size() - comma - 1) % 4 != 0) return std::nullopt;
  return out;
}

std::string uri_problem(const fs::path& folder, const std::string& uri, bool allow_outside) {
  if (uri.empty()) return "empty URI";
  const size_t colon = uri.find(':');
  const size_t slash = uri.find('/');
  if (colon != std::string::npos && (slash == std::string::npos || colon < slash))
    return "URI '" + uri + "' has a scheme; only relative file paths and data URIs are read";
  const fs::path relative = percent_decode(uri);
  if (relative.is_absolute() && !allow_outside)
    return "URI '" + uri + "' is an absolute path (pass --allow-outside-uris to read it)";
  const fs::path resolved = (folder / relative).lexically_normal();
  if (!allow_outside) {
    const fs::path root = fs::weakly_canonical(folder);
    const fs::path target = fs::weakly_canonical(resolved);
    const auto [root_end, ignored] = std::mismatch(root.begin(), root.end(), target.begin(), target.end());
    if (root_end != root.end())
      return "URI '" + uri + "' points outside the asset's folder (pass --allow-outside-uris to read it)";
  }
  std::error_code ec;
  if (!fs::is_regular_file(resolved, ec)) return "file not found: '" + uri + "'";
  return {};
}

}  // namespace gltf_pbr
