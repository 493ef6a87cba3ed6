// SIMD lanes through GCC/Clang vector extensions: kLanes floats side by side, each lane an
// independent computation, so a lane's answer never depends on its neighbours. Plain x86-64 code
// holds a Floats in two SSE registers; a function built with GLTF_PBR_LANE_CLONES also gets an
// AVX2 + FMA clone that holds it in one, picked at load time where the processor has them.
#pragma once
#include <cstdint>

namespace gltf_pbr::lanes {

constexpr int kLanes = 8;
using Floats = float __attribute__((vector_size(kLanes * sizeof(float))));
using Ints = std::int32_t __attribute__((vector_size(kLanes * sizeof(std::int32_t))));
using Mask = Ints;  // a comparison's result: all bits set where it holds
// The same lanes in double (two AVX2 registers, four SSE ones), for sums that float would round away.
using Doubles = double __attribute__((vector_size(kLanes * sizeof(double))));

#define GLTF_PBR_INLINE [[gnu::always_inline]] inline
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define GLTF_PBR_LANE_CLONES [[gnu::target_clones("arch=x86-64-v3", "default")]]
#else
#define GLTF_PBR_LANE_CLONES
#endif

GLTF_PBR_INLINE Floats splat(float v) { return Floats{} + v; }
GLTF_PBR_INLINE Floats select(Mask mask, Floats yes, Floats no) {
  return reinterpret_cast<Floats>((reinterpret_cast<Mask>(yes) & mask) | (reinterpret_cast<Mask>(no) & ~mask));
}
GLTF_PBR_INLINE Floats max(Floats a, Floats b) { return select(a > b, a, b); }
GLTF_PBR_INLINE Floats min(Floats a, Floats b) { return select(a < b, a, b); }
GLTF_PBR_INLINE Floats abs(Floats a) { return reinterpret_cast<Floats>(reinterpret_cast<Ints>(a) & 0x7FFFFFFF); }
GLTF_PBR_INLINE Doubles to_doubles(Floats v) { return __builtin_convertvector(v, Doubles); }
GLTF_PBR_INLINE Floats to_floats(Doubles v) { return __builtin_convertvector(v, Floats); }
GLTF_PBR_INLINE Floats to_floats(Ints v) { return __builtin_convertvector(v, Floats); }
GLTF_PBR_INLINE Ints truncate(Floats v) { return __builtin_convertvector(v, Ints); }  // toward 0, as a cast
// Lane by lane; one SIMD instruction where the file is built with -fno-math-errno.
GLTF_PBR_INLINE Floats square_root(Floats x) {
  Floats root;
  for (int l = 0; l < kLanes; ++l) root[l] = __builtin_sqrtf(x[l]);
  return root;
}
GLTF_PBR_INLINE bool any(Mask mask) {
  for (int l = 0; l < kLanes; ++l)
    if (mask[l]) return true;
  return false;
}
GLTF_PBR_INLINE bool all(Mask mask) {
  for (int l = 0; l < kLanes; ++l)
    if (!mask[l]) return false;
  return true;
}

}  // namespace gltf_pbr::lanes
