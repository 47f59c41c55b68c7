// Sixteen floats as one value, for the denoiser's kernels: GCC's vector extension, one AVX-512
// register, two AVX2 or four SSE ones in the clones of math/simd.h's kernels. Every operation is
// lane by lane (no sums across lanes), so each ISA computes the same bits. Values are loaded and
// stored by reference: a vector passed by value across a function boundary would depend on the
// ISA's calling convention.
#pragma once

#include <cstring>

namespace anamorph::nfor {

inline constexpr int kLanes = 16;
typedef float Lanes __attribute__((vector_size(kLanes * sizeof(float))));

[[gnu::always_inline]] inline void load(Lanes& v, const float* p) { std::memcpy(&v, p, sizeof v); }
[[gnu::always_inline]] inline void store(float* p, const Lanes& v) { std::memcpy(p, &v, sizeof v); }

}  // namespace anamorph::nfor
