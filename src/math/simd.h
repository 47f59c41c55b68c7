// Function multi-versioning for the vectorized kernels (camera batches): each is compiled for
// x86-64-v4 (AVX-512 with BW/DQ/VL), x86-64-v3 (AVX2, FMA) and the baseline, and the loader picks
// the best the CPU has. A plain "avx512f" clone is not enough: without AVX-512BW/VL GCC finds no
// vector type for loops that mix double lanes with bool masks and leaves them scalar.
// -ffp-contract=off (src/CMakeLists.txt) keeps the clones bit-identical to each other.
// A lambda inside a kernel needs __attribute__((always_inline)): it is compiled for the default
// target, is not inlined into the clone before the vectorizer runs, and leaves the loop scalar.
#pragma once

// (Not under ThreadSanitizer: the clones' ifunc resolvers run while the dynamic loader relocates
// the program, before TSan's runtime is up, and crash there.)
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#define ANAMORPH_SIMD_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define ANAMORPH_SIMD_CLONES
#endif

#include <type_traits>

namespace anamorph {

// Calls kernel(m) with m = std::integral_constant<int, kFull> when n == kFull, the constant 1
// when n == 1, else n. Inlined into a clone, a kernel looping to a constant vectorizes without a
// remainder loop (full packets) or becomes straight-line code (one-at-a-time rays).
template <int kFull, class Kernel>
[[gnu::always_inline]] inline void with_trip_count(int n, Kernel&& kernel) {
  if (n == kFull)
    kernel(std::integral_constant<int, kFull>{});
  else if (n == 1)
    kernel(std::integral_constant<int, 1>{});
  else
    kernel(n);
}

}  // namespace anamorph
