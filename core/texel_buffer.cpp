// Huge-page backed per-pixel buffers (see texel_buffer.hpp).
#include "core/texel_buffer.hpp"

#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace gltf_pbr {

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
}  // namespace

void* allocate_texels(std::size_t bytes) {
  if (bytes < kHugePage) {
    if (void* small = std::malloc(bytes == 0 ? 1 : bytes)) return small;
    throw std::bad_alloc();
  }
  const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  void* pointer = std::aligned_alloc(kHugePage, rounded);
  if (!pointer) throw std::bad_alloc();
#if defined(MADV_HUGEPAGE)
  madvise(pointer, rounded, MADV_HUGEPAGE);  // advice only: without THP the pages stay 4 KiB
#endif
  return pointer;
}

void free_texels(void* pointer, std::size_t) noexcept { std::free(pointer); }

}  // namespace gltf_pbr
