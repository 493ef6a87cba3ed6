// Per-pixel buffers in whole 2 MiB regions, kept warm between uses (see texel_buffer.hpp).
#include "core/texel_buffer.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <vector>

#if defined(__linux__)
#include <pthread.h>
#include <sys/mman.h>
#ifndef MAP_FIXED_NOREPLACE  // Linux 4.17; C libraries before glibc 2.28 do not name it
#define MAP_FIXED_NOREPLACE 0x100000
#endif
#endif

namespace gltf_pbr {

namespace {
// Large buffers take whole regions of 2 MiB, so that freed ones join and serve later ones of
// other sizes, each a huge page where the kernel has one (advise_huge_pages).
constexpr std::size_t kRegion = std::size_t{2} << 20;

#if defined(__linux__)

std::size_t rounded_to_regions(std::size_t bytes) { return (bytes + kRegion - 1) / kRegion * kRegion; }

// Memory that large buffers gave back, kept mapped for the next ones. A page a process touches
// for the first time costs the kernel a fault and a zeroing, and under a hypervisor that hands
// freed memory back to the host (virtio-balloon free page reporting) the host's fault too; pages
// kept cost none of that again (texel_buffer.hpp, advise_huge_pages, has the figures of two VMs).
// Buffers reuse the pages of the ones freed before them (decoded maps before the render's
// G-buffers): the smallest idle region that holds a request serves it. Regions are never moved
// together (mremap): a region that spans two mappings cannot be moved on Linux before 6.17, and
// before 6.11 a failed MREMAP_FIXED has already unmapped its destination. Instead, each mapping
// is placed right below the one before when that address range is free (the kernel hands out
// addresses top down), so that buffers made one after another lie end to end, and idle regions
// that touch are one region: three freed 4, 4 and 12 MB maps of a conversion then hold a 16 MB
// visibility buffer that none of them holds alone. Memory is the same to the program across
// the seam of two mappings; no call is needed to reuse it.
// Idle pages are advised MADV_FREE, so memory pressure reclaims them, and at most kIdleTexelLimit
// bytes stay idle: the rest are unmapped as before. Pages are kept only inside a TexelPageReuse
// scope: a whole-library conversion kept them at no gain in speed and 30% more peak memory.
class WarmPages {
 public:
  static constexpr std::size_t kMaxIdleRegions = 64;

  WarmPages() { idle_.reserve(kMaxIdleRegions); }

  // A child forked while another thread held the lock would wait on it forever (--isolate forks).
  void lock_for_fork() { mutex_.lock(); }
  void unlock_after_fork() { mutex_.unlock(); }

  void* take(std::size_t bytes) {
    std::lock_guard lock(mutex_);
    // The smallest idle region that holds the request; what it has beyond stays idle.
    auto fit = idle_.end();
    for (auto r = idle_.begin(); r != idle_.end(); ++r)
      if (r->bytes >= bytes && (fit == idle_.end() || r->bytes < fit->bytes)) fit = r;
    if (fit != idle_.end()) {
      char* base = fit->base;
      release_from_idle(fit, bytes);
      return base;
    }
    return map_region(bytes);
  }

  std::size_t idle_bytes() {
    std::lock_guard lock(mutex_);
    return idle_bytes_;
  }

  void begin_reuse() {
    std::lock_guard lock(mutex_);
    ++reuse_scopes_;
  }
  void end_reuse() {
    std::lock_guard lock(mutex_);
    if (--reuse_scopes_ > 0) return;
    for (const Region& region : idle_) munmap(region.base, region.bytes);
    idle_.clear();
    idle_bytes_ = 0;
  }

  void give(void* pointer, std::size_t bytes) noexcept {
    char* base = static_cast<char*>(pointer);
    std::lock_guard lock(mutex_);
    const auto touches = [&](const Region& r) { return r.base + r.bytes == base || base + bytes == r.base; };
    if (reuse_scopes_ == 0 || bytes > kIdleTexelLimit ||
        (idle_.size() == idle_.capacity() && std::none_of(idle_.begin(), idle_.end(), touches))) {
      munmap(base, bytes);  // (a full list is not grown here: growing could throw)
      return;
    }
    madvise(base, bytes, MADV_FREE);
    idle_bytes_ += bytes;
    // Joined with the idle regions it touches: the merged region takes the later place in the
    // list (the oldest are unmapped first), so a freed neighbour does not go early.
    for (auto r = idle_.begin(); r != idle_.end();) {
      if (touches(*r)) {
        base = std::min(base, r->base), bytes += r->bytes;
        r = idle_.erase(r);
      } else {
        ++r;
      }
    }
    idle_.push_back({base, bytes});
    while (idle_bytes_ > kIdleTexelLimit) {  // the oldest go first, no more of them than the excess
      Region& oldest = idle_.front();        // (sizes and the limit are whole regions)
      const std::size_t excess = std::min(oldest.bytes, idle_bytes_ - kIdleTexelLimit);
      if (munmap(oldest.base, excess) != 0) break;  // (splitting a mapping can fail at vm.max_map_count)
      oldest.base += excess, oldest.bytes -= excess, idle_bytes_ -= excess;
      if (oldest.bytes == 0) idle_.erase(idle_.begin());
    }
  }

 private:
  struct Region {
    char* base;
    std::size_t bytes;
  };

  // Takes the first `bytes` of an idle region; its remainder (2 MiB-aligned) stays idle.
  void release_from_idle(std::vector<Region>::iterator region, std::size_t bytes) {
    idle_bytes_ -= bytes;
    if (region->bytes > bytes) {
      region->base += bytes;
      region->bytes -= bytes;
    } else {
      idle_.erase(region);
    }
  }

  // A mapping of `bytes` (whole regions): right below the last one when that range is free, else
  // wherever the kernel puts it.
  char* map_region(std::size_t bytes) {
    void* mapped = MAP_FAILED;
    if (const auto top = reinterpret_cast<std::uintptr_t>(below_); top > bytes) {
      void* const wanted = reinterpret_cast<void*>(top - bytes);
      mapped = mmap(wanted, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED_NOREPLACE, -1, 0);
      if (mapped != wanted && mapped != MAP_FAILED) {  // a kernel before 4.17 took it as a hint only
        munmap(mapped, bytes);
        mapped = MAP_FAILED;
      }
    }
    if (mapped == MAP_FAILED) mapped = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED) return nullptr;
    // The whole mapping, not only its aligned inside: one advice keeps it one area of the kernel's
    // (mappings end to end then merge; give() notes why the count of areas matters).
    madvise(mapped, bytes, MADV_HUGEPAGE);
    return below_ = static_cast<char*>(mapped);
  }

  std::mutex mutex_;
  std::vector<Region> idle_;
  std::size_t idle_bytes_ = 0;
  int reuse_scopes_ = 0;
  char* below_ = nullptr;  // the start of the last mapping: the next goes right below it if it can
};

WarmPages& warm_pages() {
  static WarmPages* pages = [] {
    auto* made = new WarmPages;  // never destroyed: buffers may be freed during exit
    pthread_atfork([] { warm_pages().lock_for_fork(); }, [] { warm_pages().unlock_after_fork(); },
                   [] { warm_pages().unlock_after_fork(); });
    return made;
  }();
  return *pages;
}

void* allocate_large(std::size_t bytes) { return warm_pages().take(rounded_to_regions(bytes)); }
void free_large(void* pointer, std::size_t bytes) noexcept { warm_pages().give(pointer, rounded_to_regions(bytes)); }
std::size_t idle_large_bytes() { return warm_pages().idle_bytes(); }
void begin_reuse() { warm_pages().begin_reuse(); }
void end_reuse() { warm_pages().end_reuse(); }

#else

void* allocate_large(std::size_t bytes) { return std::malloc(bytes); }
void free_large(void* pointer, std::size_t) noexcept { std::free(pointer); }
std::size_t idle_large_bytes() { return 0; }
void begin_reuse() {}
void end_reuse() {}

#endif
}  // namespace

#if defined(__linux__)
void advise_huge_pages(void* pointer, std::size_t bytes) noexcept {
  const auto begin = reinterpret_cast<std::uintptr_t>(pointer);
  const std::uintptr_t first = (begin + kRegion - 1) / kRegion * kRegion, end = (begin + bytes) / kRegion * kRegion;
  // Advice only: where it is refused (THP off, an old kernel), the pages are 4 KiB as before.
  if (end > first) madvise(reinterpret_cast<void*>(first), end - first, MADV_HUGEPAGE);
}
#else
void advise_huge_pages(void*, std::size_t) noexcept {}
#endif

void* allocate_texels(std::size_t bytes) {
  void* pointer = bytes < kRegion ? std::malloc(bytes == 0 ? 1 : bytes) : allocate_large(bytes);
  if (!pointer) throw std::bad_alloc();
  return pointer;
}

void free_texels(void* pointer, std::size_t bytes) noexcept {
  if (!pointer) return;
  if (bytes < kRegion)
    std::free(pointer);
  else
    free_large(pointer, bytes);
}

std::size_t idle_texel_bytes() { return idle_large_bytes(); }

TexelPageReuse::TexelPageReuse() { begin_reuse(); }
TexelPageReuse::~TexelPageReuse() { end_reuse(); }

}  // namespace gltf_pbr
