// Per-pixel and per-texel buffers that the code filling them initialises (see
// DefaultInitAllocator), in mappings of their own when large: the renderer's G-buffers, decoded
// images and baked maps.
#pragma once
#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace gltf_pbr {

// Memory of per-pixel buffers: from 2 MiB up, mappings of whole 2 MiB regions advised as
// transparent huge pages (advise_huge_pages). While a TexelPageReuse lives, a freed
// large buffer's pages stay mapped for the next ones, up to kIdleTexelLimit bytes
// (texel_buffer.cpp says why). `bytes` must be the allocated size.
void* allocate_texels(std::size_t bytes);
void free_texels(void* pointer, std::size_t bytes) noexcept;
inline constexpr std::size_t kIdleTexelLimit = std::size_t{256} << 20;
std::size_t idle_texel_bytes();  // freed pages kept for reuse now (0 where none are kept)

// Asks the kernel to back the whole 2 MiB pages inside [pointer, pointer + bytes) with transparent
// huge pages at first touch (MADV_HUGEPAGE; THP's usual "madvise" mode does so only where asked),
// for large buffers not yet written: the texel regions above, and the heap buffers of a PNG's
// encode and decode (its filtered rows, zlib stream and file). The first touch of memory costs a
// fault a page; on session 39's VM a 4 KiB page's costs 2.5 ms per MB, a huge page's 1.1-1.6 ms per MB
// when the host had taken the memory back and 0.06 when it had not: Avocado 4096² converted in
// 0.66-0.74 s against 0.98, at 4 MB more peak memory (4-11 MB on the smaller runs of
// bench/ab.sh; bench/RESULTS.md, session 39). Session 31's VM was the other way round for memory
// the host had taken back (0.4-0.5 against 2.0-2.3 ms per MB), so this is measured, not universal.
void advise_huge_pages(void* pointer, std::size_t bytes) noexcept;

// Where buffers follow buffers of like size (a preview: the render's G-buffers after the
// conversion's maps), the pages of the freed ones serve the next. Elsewhere (a conversion alone)
// keeping them would only raise the peak memory, so they are unmapped as they are freed, and
// when the last reuse scope of the process ends, the idle ones go too.
class TexelPageReuse {
 public:
  TexelPageReuse();
  ~TexelPageReuse();
  TexelPageReuse(const TexelPageReuse&) = delete;
  TexelPageReuse& operator=(const TexelPageReuse&) = delete;
};

// An allocator whose resize() default-initialises: trivial texels stay unwritten until the pass
// that fills them, so each thread first-touches its own rows of a fresh buffer in parallel, and
// every byte is written once instead of by a serial memset and then again (at 1024^2 the two
// G-buffers are 30 MB: the memset and its page faults cost as much as a third of the pass; zeroing
// a decoded 2048² map before the decoder wrote it was a fifth of a conversion that needs no solve).
template <typename T>
struct DefaultInitAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <typename U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_texels(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { free_texels(p, n * sizeof(T)); }
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <typename T>
using TexelBuffer = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace gltf_pbr
