// What every camera shares: the hand-off of sample positions to batch kernels.
#include "camera/camera.h"

#include <cstring>

#include "math/simd.h"

namespace anamorph {

// In a full packet the arrays are written as vectors: the kernels read them as vectors, and a
// vector load waits for scalar stores to reach the cache (no store-to-load forwarding).
namespace {

ANAMORPH_KERNEL_BODY void split_body(const CameraSample* s, int n, double* __restrict u,
                                     double* __restrict v) {
  if (n != kCameraBatch) {
    for (int i = 0; i < n; ++i) u[i] = s[i].uv.x, v[i] = s[i].uv.y;
    return;
  }
  static_assert(kCameraBatch % 8 == 0, "full packets are split eight lanes at a time");
  using D2 = double __attribute__((vector_size(16)));
  using D4 = double __attribute__((vector_size(32)));
  using D8 = double __attribute__((vector_size(64)));
  for (int h = 0; h < kCameraBatch; h += 8) {
    D2 a[8];
    for (int i = 0; i < 8; ++i) std::memcpy(&a[i], &s[h + i].uv, sizeof(D2));
    const D4 b0 = __builtin_shufflevector(a[0], a[1], 0, 1, 2, 3);
    const D4 b1 = __builtin_shufflevector(a[2], a[3], 0, 1, 2, 3);
    const D4 b2 = __builtin_shufflevector(a[4], a[5], 0, 1, 2, 3);
    const D4 b3 = __builtin_shufflevector(a[6], a[7], 0, 1, 2, 3);
    const D8 c0 = __builtin_shufflevector(b0, b1, 0, 1, 2, 3, 4, 5, 6, 7);
    const D8 c1 = __builtin_shufflevector(b2, b3, 0, 1, 2, 3, 4, 5, 6, 7);
    const D8 us = __builtin_shufflevector(c0, c1, 0, 2, 4, 6, 8, 10, 12, 14);
    const D8 vs = __builtin_shufflevector(c0, c1, 1, 3, 5, 7, 9, 11, 13, 15);
    std::memcpy(u + h, &us, sizeof(D8));
    std::memcpy(v + h, &vs, sizeof(D8));
  }
}

}  // namespace

void split_sample_positions(const CameraSample* s, int n, double* u, double* v) {
  simd::Kernel<split_body>{}(s, n, u, v);
}

}  // namespace anamorph
