// sampling/x86_lanes.h — the x86 vector intrinsics that the samplers' and warps' lanes use (sobol_lanes.cpp,
// warp_lanes.cpp), where the compiler can target them function by function (GCC or Clang on x86-64):
// SYMPHONG_X86_LANES is defined there, and each lane function names its instruction sets in a target attribute
// and runs only after a run-time check of the processor. Elsewhere the files keep only their scalar forms.
#pragma once

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SYMPHONG_X86_LANES 1
// GCC 12 reads the intrinsics' deliberately undefined pass-through operand (_mm512_undefined_epi32) as
// "maybe uninitialized" where they are inlined: a false warning inside the compiler's own header.
#if !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>
#if !defined(__clang__)
#pragma GCC diagnostic pop
#endif

namespace symphong {
/// Whether this processor runs AVX-512 F (asked once).
inline bool avx512fAvailable() {
    static const bool available = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx512f") != 0;
    }();
    return available;
}
}  // namespace symphong
#endif
